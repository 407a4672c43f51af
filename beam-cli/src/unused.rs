//! What of a scene a render does not use, said on stderr before it starts: the loader's notices
//! (one line per kind, with its count) and what the chosen method and backend leave out (cut-outs,
//! normal textures). Said even when `--quiet`: the image lacks
//! content the file holds.

use crate::method::Kind;
use beam_scene::scene::Scene;

/// Say on stderr what of `scene` a render by `kind` does not use; `gpu_gather`: a glossy render
/// asked of the GPU with second-order shadows (whose gather then runs on the host with cut-outs).
pub(crate) fn warn(scene: &Scene, kind: Kind, gpu_gather: bool) {
    for n in &scene.notices {
        // Said even when `quiet`: the image lacks content the file holds.
        eprintln!("warning: {}: {} {}", scene.name, n.count, n.what);
    }
    // Every method reads textures on both backends (the GPU hands textured points to the host),
    // and the rays and nonlinear beams see through cut-outs where their alpha says; the glossy
    // light beams scatter off whole triangles, and the GPU's gather, whose second-order shadow
    // rays test no alpha, runs on the host instead.
    if scene.has_cut_outs() && kind == Kind::Glossy {
        let gather = if gpu_gather {
            "; the gather runs on the host (the GPU's second-order shadow rays test no alpha)"
        } else {
            ""
        };
        eprintln!(
            "warning: {}: cut-out materials (alphaMode MASK or BLEND) are seen through by the rays of --method \
             glossy but scatter its light beams whole{gather}",
            scene.name
        );
    }
    let normal_maps = scene.surfaces.maps.iter().any(|m| m.normal.is_some());
    if normal_maps && matches!(kind, Kind::Glossy | Kind::GlossyReference) {
        eprintln!(
            "warning: {}: normal textures bend the direct light of --method {} but not the scattered light it \
             gathers",
            scene.name,
            kind.name()
        );
    }
}
