//! `beam render`'s options checked before any work: values in range, options that apply to the
//! method, output paths that may be written, and the memory the render will need. [`plan`] renders
//! nothing, so it can be run on any argument vector (the CLI fuzzer does).

use beam_math::glossy::VolumeMethod;
use beam_render::nonlinear::Degree;
use beam_render::options::{Method, Occluders, RenderOptions, Shading};
use beam_scene::region::Placement;
use beam_scene::scene::{self, Environment, EnvironmentMap, Scene};
use std::path::Path;

/// Options of `beam render`.
pub struct RenderArgs<'a> {
    pub scene: &'a str,
    pub method: &'a str,
    pub backend: &'a str,
    pub degree: &'a str,
    pub texels: u32,
    pub bounces: u32,
    pub caustic_strata: u32,
    pub smesh: Option<u32>,
    /// `--smesh-target`: faces of the simplified S mesh.
    pub smesh_target: Option<u32>,
    /// `--smesh-error`: error of the simplified S mesh.
    pub smesh_error: Option<f32>,
    pub shading: &'a str,
    pub spp: u32,
    pub primary_spp: u32,
    pub primary_beams: bool,
    pub occluders: &'a str,
    pub exact: bool,
    pub volume: &'a str,
    pub linear_gather: bool,
    pub subdivide: u32,
    pub second_order: bool,
    pub photon_kernel: bool,
    pub photons: u64,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub out: &'a Path,
    /// Scale of the written image, 2^exposure.
    pub exposure: f32,
    /// `--tile I/N`.
    pub tile: Option<&'a str>,
    /// `--crop x0,y0,x1,y1`.
    pub crop: Option<&'a str>,
    /// `--frame K`.
    pub frame: Option<u32>,
    pub stats: Option<&'a Path>,
    /// Let a scene file name meshes outside its folder.
    pub allow_outside_paths: bool,
    /// `--env`: an environment map file or `r,g,b`, replacing the scene's.
    pub env: Option<&'a str>,
    /// The clap ids of the options given on the command line (not defaulted).
    pub given: &'a [String],
}

/// Largest image side, and largest pixel count.
pub const MAX_SIDE: u32 = 16384;
/// Largest `--primary-spp` (32 × 32 stratified rays).
pub const MAX_PRIMARY_SPP: u32 = 1024;

/// What `--method` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Beam,
    Ray,
    Nonlinear,
    NonlinearReference,
    Glossy,
    GlossyReference,
}

impl Kind {
    const ALL: [(&'static str, Kind); 6] = [
        ("beam", Kind::Beam),
        ("ray", Kind::Ray),
        ("nonlinear", Kind::Nonlinear),
        ("nonlinear-reference", Kind::NonlinearReference),
        ("glossy", Kind::Glossy),
        ("glossy-reference", Kind::GlossyReference),
    ];

    fn parse(s: &str) -> Result<Self, String> {
        Self::ALL
            .iter()
            .find(|(n, _)| *n == s)
            .map(|&(_, k)| k)
            .ok_or_else(|| format!("unknown method `{s}` (expected {})", Self::ALL.map(|(n, _)| n).join(", ")))
    }

    /// The `--method` name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, k)| *k == self).map_or("?", |(n, _)| n)
    }
}

/// Largest `|--exposure|`.
pub const MAX_EXPOSURE: f32 = 64.0;

/// A validated render: everything `beam render` needs but the adapter.
pub struct Plan {
    pub kind: Kind,
    /// The scene, its camera at `--frame`.
    pub scene: Scene,
    /// Size, shading, shadow and primary samples, and the region (`--tile`, `--crop`).
    pub options: RenderOptions,
    /// Where the rendered pixels sit in the frame (the whole frame without `--tile` or `--crop`).
    pub placement: Placement,
    pub degree: Degree,
    pub volume: VolumeMethod,
    pub gpu: bool,
}

/// The methods an option applies to (`None`: every method), by clap id.
fn applies_to(id: &str, gpu: bool, primary_beams: bool) -> Option<&'static [Kind]> {
    use Kind::*;
    Some(match id {
        "degree" | "texels" | "bounces" | "caustic_strata" | "smesh_target" | "smesh_error" => &[Nonlinear],
        "shading" => &[Beam, Ray, Nonlinear, NonlinearReference],
        "spp" if gpu => &[Ray, Nonlinear, NonlinearReference],
        "spp" => &[Beam, Ray],
        "primary_spp" if primary_beams => &[Ray],
        "primary_spp" => &[Beam, Ray],
        "primary_rays" | "occluders" | "exact" => &[Beam],
        "volume" | "linear_gather" | "subdivide" | "no_second_order" | "photon_kernel" => &[Glossy],
        "photons" => &[NonlinearReference, GlossyReference],
        _ => return None,
    })
}

fn flag(id: &str) -> String {
    format!("--{}", id.replace('_', "-"))
}

fn range<T: PartialOrd + std::fmt::Display>(id: &str, v: T, lo: T, hi: T) -> Result<(), String> {
    if v < lo || v > hi {
        return Err(format!("{} {v} out of range ({lo} to {hi})", flag(id)));
    }
    Ok(())
}

/// The image size: `--width` and `--height`, else the camera's (keeping its aspect when only the
/// width is given), each side in 1 to [`MAX_SIDE`]. No arithmetic here can wrap.
pub fn image_size(width: Option<u32>, height: Option<u32>, camera: (u32, u32)) -> Result<(u32, u32), String> {
    let (cw, ch) = camera;
    let w = u64::from(width.unwrap_or(cw));
    let h = match (width, height) {
        (_, Some(h)) => u64::from(h),
        (Some(_), None) => ((w * u64::from(ch) + u64::from(cw.max(1)) / 2) / u64::from(cw.max(1))).max(1),
        (None, None) => u64::from(ch),
    };
    let side = 1..=u64::from(MAX_SIDE);
    if !side.contains(&w) || !side.contains(&h) {
        let from = if width.is_none() || height.is_none() { format!(" (camera {cw}×{ch})") } else { String::new() };
        return Err(format!("image size {w}×{h}{from} out of range: each side must be 1 to {MAX_SIDE}"));
    }
    Ok((w as u32, h as u32))
}

/// Refuse a `--scene` path that exists and is not a regular file (a FIFO would block, a device
/// never end), before the loader opens it.
fn check_scene_path(s: &str) -> Result<(), String> {
    if scene::BUILTIN.contains(&s) {
        return Ok(());
    }
    match std::fs::metadata(s) {
        Ok(m) if !m.is_file() => Err(format!("--scene {s}: not a regular file")),
        _ => Ok(()),
    }
}

/// Peak memory of a render, in bytes: per-pixel buffers (the image, its bands, its 8-bit copy and
/// encoding, and each method's per-pixel data), the scene, and the nonlinear reference's photons.
/// The per-pixel figures are the peak resident sizes measured at 512² and 1024² (release build, the
/// built-ins; the nonlinear method's depends on the scene, mirror-glass is the largest seen) with a
/// margin of about a third.
pub fn estimate(kind: Kind, width: u32, height: u32, triangles: usize, photons: u64) -> u64 {
    let pixels = u64::from(width) * u64::from(height);
    let per_pixel = match kind {
        Kind::Beam | Kind::Ray => 32,
        Kind::Nonlinear => 640,
        Kind::NonlinearReference | Kind::Glossy | Kind::GlossyReference => 384,
    };
    let per_photon = if kind == Kind::NonlinearReference { 32 } else { 0 };
    crate::limits::bytes(&[(pixels, per_pixel), (triangles as u64, 256), (photons, per_photon), (1, 64 << 20)])
}

/// Check every option of `beam render` and load the scene; `quiet` leaves out the memory note.
pub fn plan(a: &RenderArgs, quiet: bool) -> Result<Plan, String> {
    let kind = Kind::parse(a.method)?;
    let gpu = match a.backend {
        "cpu" => false,
        "gpu" => true,
        b => return Err(format!("unknown backend `{b}` (expected cpu or gpu)")),
    };
    if gpu && kind == Kind::GlossyReference {
        return Err(
            "--backend gpu does not apply to --method glossy-reference (its photon tracing runs on the CPU)".into()
        );
    }
    for id in a.given {
        if let Some(kinds) = applies_to(id, gpu, a.primary_beams) {
            if !kinds.contains(&kind) {
                let to = kinds.iter().map(|k| k.name()).collect::<Vec<_>>().join(", ");
                let backend = if gpu { " --backend gpu" } else { "" };
                return Err(format!(
                    "{} does not apply to --method {}{backend} (it applies to: {to})",
                    flag(id),
                    kind.name()
                ));
            }
        }
    }
    if gpu && kind == Kind::Glossy && (a.linear_gather || a.photon_kernel) {
        return Err(
            "--linear-gather and --photon-kernel do not apply to --backend gpu (the GPU gather walks the cone \
             hierarchy at each point)"
                .into(),
        );
    }
    let shading = match a.shading {
        "fraction" => Shading::Fraction,
        "exact" => Shading::Exact,
        s => return Err(format!("unknown --shading `{s}` (expected exact or fraction)")),
    };
    let occluders = match a.occluders {
        "auto" => Occluders::Auto,
        "split" => Occluders::Split,
        "edges" => Occluders::Edges,
        o => return Err(format!("unknown --occluders `{o}` (expected auto, split or edges)")),
    };
    let degree = match a.degree {
        "s1" => Degree::S1,
        "s3" => Degree::S3,
        d => return Err(format!("unknown --degree `{d}` (expected s1 or s3)")),
    };
    let volume = match a.volume {
        "exact" => VolumeMethod::Exact,
        "tessellated" => VolumeMethod::Tessellated,
        v => return Err(format!("unknown --volume `{v}` (expected exact or tessellated)")),
    };
    // The nonlinear tracer sizes beam regions from 4 texels up to `--texels`.
    range("texels", a.texels, 4, 4096)?;
    range("bounces", a.bounces, 1, 16)?;
    range("caustic_strata", a.caustic_strata, 0, beam_cpu::nonlinear::MAX_CAUSTIC_STRATA)?;
    range("spp", a.spp, 1, 65536)?;
    range("subdivide", a.subdivide, 1, 64)?;
    range("photons", a.photons, 1, 1 << 36)?;
    let k = a.primary_spp.isqrt();
    if a.primary_spp == 0 || a.primary_spp > MAX_PRIMARY_SPP || k * k != a.primary_spp {
        return Err(format!(
            "--primary-spp {} must be a perfect square from 1 to {MAX_PRIMARY_SPP} (1, 4, 9, 16, …: a k × k grid \
             of stratified rays)",
            a.primary_spp
        ));
    }
    if !(a.exposure.is_finite() && a.exposure.abs() <= MAX_EXPOSURE) {
        return Err(format!("--exposure {} out of range (-{MAX_EXPOSURE} to {MAX_EXPOSURE})", a.exposure));
    }
    if let (Some(0), _) | (_, Some(0)) = (a.width, a.height) {
        return Err(format!("image size out of range: each side must be 1 to {MAX_SIDE}"));
    }
    crate::output::check_render_outputs(a.out, a.stats)?;
    check_scene_path(a.scene)?;
    let mut scene = match a.smesh {
        Some(n) => scene::builtin_with_smesh(a.scene, n).map_err(|e| e.to_string())?,
        None => scene::load_with(a.scene, &scene::LoadOptions { allow_outside_paths: a.allow_outside_paths })
            .map_err(|e| e.to_string())?,
    };
    let simplify = match (a.smesh_target, a.smesh_error) {
        (Some(n), _) => Some(scene::Simplify::Faces(n)),
        (None, Some(e)) => Some(scene::Simplify::Error(e)),
        (None, None) => None,
    };
    if let Some(s) = simplify {
        let flag = if a.smesh_target.is_some() { "--smesh-target" } else { "--smesh-error" };
        let value = a.smesh_target.map_or_else(|| format!("{}", a.smesh_error.unwrap_or(0.0)), |n| n.to_string());
        scene.smesh.rest = Some(s.checked().map_err(|e| format!("{flag} {value} out of range: {e}"))?);
    }
    if let Some(e) = a.env {
        scene.environment = environment(e)?;
    }
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
    if let Some(k) = a.frame {
        scene.camera = camera_at(&scene, k)?;
    }
    let (width, height) = image_size(a.width, a.height, (scene.camera.width, scene.camera.height))?;
    // Every camera (the scene file's, a glTF camera, the framing camera of a bare mesh, a frame of
    // a camera path) at the size rendered: one that cannot see is refused with its reason.
    scene.camera.with_size(width, height).check_view().map_err(|why| match a.frame {
        Some(k) => format!("--frame {k}: the camera of scene {}: {why}", scene.name),
        None => format!("the camera of scene {}: {why}", scene.name),
    })?;
    let region = crate::region::parse(a.tile, a.crop, width, height)?;
    let memory = estimate(kind, width, height, scene.triangles.len(), a.photons);
    crate::limits::admit(&format!("a {width}×{height} {} render", kind.name()), memory, quiet)?;
    let options = RenderOptions {
        method: if kind == Kind::Ray { Method::Ray } else { Method::Beam },
        shading,
        spp: a.spp,
        primary_spp: a.primary_spp,
        // On the GPU every shadow beam is traced to the end.
        primary_beams: a.primary_beams,
        width,
        height,
        seed: 1,
        region,
        occluders,
        exact: a.exact || gpu,
    };
    let placement = match region {
        Some(r) => Placement::new(r, width, height)
            .ok_or_else(|| format!("the region {r:?} is not inside the {width}×{height} frame"))?
            .of_render(fingerprint(a, (width, height))),
        None => Placement::whole(width, height),
    };
    Ok(Plan { kind, scene, options, placement, degree, volume, gpu })
}

/// What decides a render's pixel values, as one number (64-bit FNV-1a of every option but the
/// outputs and the region, after defaults, with the frame's size): equal for every tile of one
/// frame, different (but for a 2⁻⁶⁴ chance) for tiles of another scene, method, option, frame or
/// exposure, so that `beam merge` joins only tiles of one render. Never 0.
fn fingerprint(a: &RenderArgs, (width, height): (u32, u32)) -> u64 {
    let text = format!(
        "{}|{}|{}|{}|{}|{}|{}|{:?}|{:?}|{:?}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}×{}|{}|{:?}|{}{}",
        a.scene,
        a.method,
        a.backend,
        a.degree,
        a.texels,
        a.bounces,
        a.caustic_strata,
        a.smesh,
        a.smesh_target,
        a.smesh_error.map(f32::to_bits),
        a.shading,
        a.spp,
        a.primary_spp,
        a.primary_beams,
        a.occluders,
        a.exact,
        a.volume,
        a.linear_gather,
        a.subdivide,
        a.second_order,
        a.photon_kernel,
        a.photons,
        width,
        height,
        a.exposure.to_bits(),
        a.frame,
        a.allow_outside_paths,
        // Only when given, so that the fingerprints of renders without it stay as they were.
        a.env.map(|e| format!("|env {e}")).unwrap_or_default(),
    );
    let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3));
    hash.max(1)
}

/// The environment `--env` names: `r,g,b` (three finite numbers ≥ 0), a uniform sky of that
/// radiance, or a `.hdr` or `.exr` map file.
fn environment(arg: &str) -> Result<Environment, String> {
    let parts: Vec<&str> = arg.split(',').collect();
    if parts.len() > 1 {
        let rgb: Vec<f32> = parts.iter().filter_map(|p| p.trim().parse::<f32>().ok()).collect();
        return match rgb[..] {
            [r, g, b] if parts.len() == 3 && rgb.iter().all(|v| v.is_finite() && *v >= 0.0) => {
                Ok(Environment::Constant(beam_math::glam::Vec3::new(r, g, b)))
            }
            _ => Err(format!("--env {arg}: expected three numbers ≥ 0 (r,g,b) or a .hdr or .exr file")),
        };
    }
    let map = EnvironmentMap::load(Path::new(arg)).map_err(|e| format!("--env: {e}"))?;
    Ok(Environment::Map(std::sync::Arc::new(map)))
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

/// The camera of `--frame k`: frame `k` of the scene's camera path, which must have it.
fn camera_at(scene: &Scene, k: u32) -> Result<scene::Camera, String> {
    let camera = scene.camera_at(k).ok_or_else(|| match &scene.camera_path {
        None => format!(
            "--frame {k}: scene {} has a still camera (no [[camera.keys]] in its [camera]), so only frame 0",
            scene.name
        ),
        Some(path) => format!(
            "--frame {k} out of range: scene {}'s camera path has frames 0 to {}",
            scene.name,
            path.last_frame()
        ),
    })?;
    camera
        .check_view()
        .map_err(|why| format!("--frame {k}: the camera of scene {} at this frame: {why}", scene.name))?;
    Ok(camera)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_never_wrap() {
        assert_eq!(image_size(None, None, (640, 480)), Ok((640, 480)));
        assert_eq!(image_size(Some(320), None, (640, 480)), Ok((320, 240)));
        assert_eq!(image_size(Some(1), None, (640, 100)), Ok((1, 1)));
        assert!(image_size(Some(2), None, (2, (1 << 31) + 1)).is_err());
        assert!(image_size(None, None, (640, (1 << 31) + 1)).is_err());
        assert!(image_size(Some(16385), Some(1), (1, 1)).is_err());
        assert!(image_size(Some(u32::MAX), None, (1, u32::MAX)).is_err());
    }
}
