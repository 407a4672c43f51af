//! What of a scene a render does not use, said on stderr before it starts: the loader's notices
//! (one line per kind, with its count) and what the chosen method and backend leave out (the
//! environment, textures, cut-outs, normal textures). Said even when `--quiet`: the image lacks
//! content the file holds.

use crate::method::Kind;
use beam_scene::scene::{Environment, Scene};

/// Say on stderr what of `scene` a render by `kind` (on the GPU where `gpu`) does not use.
pub(crate) fn warn(scene: &Scene, kind: Kind, gpu: bool) {
    for n in &scene.notices {
        // Said even when `quiet`: the image lacks content the file holds.
        eprintln!("warning: {}: {} {}", scene.name, n.count, n.what);
    }
    if let Some(what) = unseen_environment(kind, gpu, &scene.environment) {
        eprintln!("warning: {}: the environment is not seen by --method {}{what}", scene.name, kind.name());
    }
    // The beam and ray frames on the GPU shade on the host, textures included.
    if gpu && !matches!(kind, Kind::Beam | Kind::Ray) && !scene.surfaces.is_plain() {
        eprintln!(
            "warning: {}: textures and vertex colours are not used by --method {} --backend gpu (its materials \
             are flat)",
            scene.name,
            kind.name()
        );
    }
    // The CPU cuts them everywhere (rays see through them where their alpha says, and so do the
    // nonlinear beams' texels) but in the glossy light beams, which scatter off whole triangles; so
    // do the beam and ray frames on the GPU, whose hits the host checks against the alpha.
    let host_driven = matches!(kind, Kind::Beam | Kind::Ray);
    if scene.has_cut_outs() && ((gpu && !host_driven) || kind == Kind::Glossy) {
        let how = if gpu {
            "are drawn opaque by --backend gpu"
        } else {
            "are seen through by the rays of --method glossy but scatter its light beams whole"
        };
        eprintln!("warning: {}: cut-out materials (alphaMode MASK or BLEND) {how}", scene.name);
    }
    // On the GPU, the methods other than beam and ray use no texture (said above).
    let normal_maps = scene.surfaces.maps.iter().any(|m| m.normal.is_some());
    if normal_maps && !gpu && matches!(kind, Kind::Glossy | Kind::GlossyReference) {
        eprintln!(
            "warning: {}: normal textures bend the direct light of --method {} but not the scattered light it \
             gathers",
            scene.name,
            kind.name()
        );
    }
}

/// What of a non-black environment `kind` (on the GPU where `gpu`) does not show, after
/// "the environment is not seen by --method X"; `None` where it shows wholly (`beam`, `ray`) or is
/// black.
fn unseen_environment(kind: Kind, gpu: bool, environment: &Environment) -> Option<&'static str> {
    if environment.is_black() {
        return None;
    }
    match kind {
        Kind::Beam | Kind::Ray => None,
        _ if gpu => Some(" --backend gpu"),
        Kind::Nonlinear | Kind::NonlinearReference => {
            Some(" in the background, mirrors and glass (it lights diffuse surfaces only)")
        }
        Kind::Glossy | Kind::GlossyReference => Some(""),
    }
}
