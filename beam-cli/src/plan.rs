//! `beam render`'s options checked before any work: values in range, options that apply to the
//! method, output paths that may be written, and the memory the render will need. [`plan`] renders
//! nothing, so it can be run on any argument vector (the CLI fuzzer does).

use crate::method::Kind;
use beam_math::glossy::VolumeMethod;
use beam_render::nonlinear::Degree;
use beam_render::options::{Method, Occluders, RenderOptions, Shading};
use beam_scene::region::Placement;
use beam_scene::scene::{self, Environment, EnvironmentMap, Scene};
use std::path::{Path, PathBuf};

/// Options of `beam render`, as parsed (the defaults filled in).
#[derive(clap::Args)]
pub(crate) struct RenderArgs {
    /// A built-in scene (cornell, mirror-glass, cornell-point, foliage; the soft-shadow suite's
    /// spheres, spheres-36, spheres-256, plant, ground), a .toml scene file, a .gltf/.glb
    /// model or an .obj mesh.
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Light visibility: `beam` (exact shadow beams) or `ray` (stratified shadow rays); or
    /// `nonlinear` (mirrors by nonlinear beams, 000, with exact shadow beams) and its ground
    /// truth `nonlinear-reference` (mirrors by rays reflected about the interpolated normal); or
    /// `glossy` (caustics and glossy light by light volumes from point lights, and from area
    /// lights as 4×4 stratified points, 002) and its ground truth `glossy-reference` (photons).
    #[arg(long, default_value = "beam")]
    pub method: String,
    /// Where the method runs: `cpu`, or `gpu` (the first wgpu adapter). On the GPU, `beam` sees
    /// through eye beams (or `--primary-rays`) and `ray` through primary rays, with shadow beams
    /// (exact, each to the end) or shadow rays, in batches, the frame driven by the host;
    /// nonlinear: beam atlases, rays and the shading of diffuse points, area lights by `--spp`
    /// stratified shadow rays, where the CPU's are exact; glossy: eye rays and the gather.
    /// `glossy-reference` runs on the CPU only.
    #[arg(long, default_value = "cpu")]
    pub backend: String,
    /// Nonlinear beam parameterization: `s1` or `s3` (`--method nonlinear`).
    #[arg(long, default_value = "s3")]
    pub degree: String,
    /// Texels per side of each nonlinear beam's region, 4 to 4096 (`--method nonlinear`).
    #[arg(long, default_value_t = 32)]
    pub texels: u32,
    /// Levels of the nonlinear beam tree (specular bounces by beams; deeper ones by rays).
    #[arg(long, default_value_t = 2)]
    pub bounces: u32,
    /// Area lights cast caustics as N × N stratified point emitters (`--method nonlinear`), 0 to
    /// 8; each costs about as much as a point light's caustics; 0: area lights cast none.
    #[arg(long, default_value_t = beam_render::nonlinear::CAUSTIC_STRATA)]
    pub caustic_strata: u32,
    /// S-mesh resolution of a procedural built-in (facing-mirrors, glass-lens, mirror-teapot,
    /// wavy-lake): quads per mirror side, lens rings, teapot profile steps, water quads per side.
    #[arg(long)]
    pub smesh: Option<u32>,
    /// Spawn the nonlinear beams from a coarse S mesh (000 §7.1) of about N faces in all,
    /// simplified from every mirror and glass surface without an S mesh of its own in the scene
    /// file (meshoptimizer), 4 to 16777216; the fine surfaces are still the ones rendered.
    #[arg(long, value_name = "N", conflicts_with = "smesh_error")]
    pub smesh_target: Option<u32>,
    /// Like `--smesh-target`, but simplify while the surface moves by at most this fraction of
    /// its size (above 0, at most 1).
    #[arg(long, value_name = "E")]
    pub smesh_error: Option<f32>,
    /// `exact` (eq. 1, Lambert's polygon formula) or `fraction` (001 eq. 2).
    #[arg(long, default_value = "exact")]
    pub shading: String,
    /// Shadow rays per shade point and area light, 1 to 65536 (`--method ray`, and `--backend gpu`;
    /// with `--method beam`, the budget of a shadow beam in rays' worth of work and the rays that
    /// sample what it leaves unresolved, see `--exact`).
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Primary rays per pixel when primary visibility is ray traced (`--method ray`, and `beam`
    /// with `--primary-rays`): a perfect square from 1 to 1024 (1, 4, 9, 16, …), the k × k
    /// strata of the pixel; any other number is refused, not rounded.
    #[arg(long, default_value_t = 1)]
    pub primary_spp: u32,
    /// With `--method beam`: primary visibility by `--primary-spp` stratified primary rays,
    /// and point-light shadows by rays, instead of the default exact eye beams (box-filtered
    /// pixel coverage, 001 §3) with hard shadows by beams from the visible pieces (001 §4.2).
    #[arg(long)]
    pub primary_rays: bool,
    /// With `--method beam`: how shadow beams take their occluders: `split` (one at a time,
    /// 001 §3.2), `edges` (by their silhouette, boundary and cut edges, integrated exactly), or
    /// `auto` (each cluster of shade points picks the one that did less work); the same image.
    #[arg(long, default_value = "auto")]
    pub occluders: String,
    /// With `--method beam`: trace every shadow beam to the end. By default a beam whose work
    /// passes `--spp` shadow rays' worth samples the part of the light it left unresolved with
    /// `--spp` rays (exact where they all agree); `--stats` gives the share of exact pixels and
    /// the largest error bound.
    #[arg(long)]
    pub exact: bool,
    /// Glossy beams' Gaussian volumes (`--method glossy`): `exact` (Owen's T) or `tessellated`
    /// (002 Figs. 11-12).
    #[arg(long, default_value = "exact")]
    pub volume: String,
    /// Gather over every light beam (`--method glossy`), as 002 does, instead of through the
    /// cone hierarchy.
    #[arg(long)]
    pub linear_gather: bool,
    /// Split each scatterer triangle into N × N sub-triangles for its light beams (`--method
    /// glossy`; 1: one beam per triangle, as 002 does).
    #[arg(long, default_value_t = 4)]
    pub subdivide: u32,
    /// Leave out second-order shadows (`--method glossy`), as 002 does.
    #[arg(long)]
    pub no_second_order: bool,
    /// Read the scattered light through the kernel of `glossy-reference`'s photon map (`--method
    /// glossy`, CPU), so the two estimate the same image: for comparisons with it.
    #[arg(long)]
    pub photon_kernel: bool,
    /// Photons per light of the references' caustics (`nonlinear-reference`,
    /// `glossy-reference`).
    #[arg(long, default_value_t = 4_000_000)]
    pub photons: u64,
    /// Image width (default: the scene camera's).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height (default: the scene camera's, or keeping its aspect with --width).
    #[arg(long)]
    pub height: Option<u32>,
    /// Output image: `*.png` (8-bit sRGB, tone-mapped by clamping) or `*.exr` (OpenEXR, linear
    /// radiance as 32-bit floats). Only a new file or a writable regular file is written; it is
    /// checked before the render starts and replaced atomically.
    #[arg(long, default_value = "beam.png")]
    pub out: PathBuf,
    /// Scale the image by 2^EV before it is written, in PNG (before the sRGB encoding) and EXR
    /// alike; -64 to 64. With an integer EV an EXR holds radiance × 2^EV exactly.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_name = "EV")]
    pub exposure: f32,
    /// Render band I of N horizontal bands (I from 0 to N − 1; rows ⌊I·H/N⌋ to ⌊(I+1)·H/N⌋,
    /// the same split in every process), for a render farm: the output holds the band and
    /// where it sits in the frame, and `beam merge` joins the bands. Each pixel gets the value
    /// the whole frame's render gives it, bit for bit; the per-pixel work is done for the band
    /// only (docs/guide.md, "Render farms", says what each method still does for the whole
    /// frame).
    #[arg(long, value_name = "I/N", conflicts_with = "crop")]
    pub tile: Option<String>,
    /// Render the pixels x0 ≤ x < x1, y0 ≤ y < y1 of the frame only (like --tile, a rectangle
    /// of it; `beam merge` joins rectangles that cover the frame).
    #[arg(long, value_name = "x0,y0,x1,y1")]
    pub crop: Option<String>,
    /// Frame K of the scene file's animated camera (`[[camera.keys]]`); a still camera has
    /// frame 0 only.
    #[arg(long, value_name = "K")]
    pub frame: Option<u32>,
    /// Also write statistics as JSON (to a file other than --out; written together with it).
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// Let a scene file name meshes outside its own folder (through `..`, an absolute path or a
    /// symbolic link); by default they must stay inside it.
    #[arg(long)]
    pub allow_outside_paths: bool,
    /// The environment, replacing the scene's: what rays that leave the scene see (the
    /// background, mirrors, glass) and the light it sends in. `r,g,b`: a uniform sky of that
    /// linear radiance (lit with exact shadow beams by `--method beam`); a `.hdr` or `.exr`
    /// file: an equirectangular map (+Y up, +X at its centre column, as glTF viewers), whose
    /// light `--spp` cosine-weighted rays a point sample. Seen by every method and lighting every
    /// method's diffuse points (`glossy` samples it by cosine-weighted rays: 64 a diffuse point,
    /// 256 a glossy one).
    #[arg(long, value_name = "FILE|r,g,b")]
    pub env: Option<String>,
    /// The clap ids of the options given on the command line (not defaulted); set after parsing.
    #[arg(skip)]
    pub given: Vec<String>,
}

impl RenderArgs {
    /// Primary visibility by eye beams (not `--primary-rays`).
    pub(crate) fn primary_beams(&self) -> bool {
        !self.primary_rays
    }

    /// Second-order shadows of the glossy light volumes (not `--no-second-order`).
    pub(crate) fn second_order(&self) -> bool {
        !self.no_second_order
    }
}

/// Largest image side, and largest pixel count.
pub(crate) const MAX_SIDE: u32 = 16384;
/// Largest `--primary-spp` (32 × 32 stratified rays).
pub(crate) const MAX_PRIMARY_SPP: u32 = 1024;

/// Largest `|--exposure|`.
pub(crate) const MAX_EXPOSURE: f32 = 64.0;

/// A validated render: everything `beam render` needs but the adapter.
pub(crate) struct Plan {
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
pub(crate) fn image_size(width: Option<u32>, height: Option<u32>, camera: (u32, u32)) -> Result<(u32, u32), String> {
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
pub(crate) fn estimate(kind: Kind, width: u32, height: u32, triangles: usize, photons: u64) -> u64 {
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
pub(crate) fn plan(a: &RenderArgs, quiet: bool) -> Result<Plan, String> {
    let kind = Kind::parse(&a.method)?;
    let gpu = match a.backend.as_str() {
        "cpu" => false,
        "gpu" => true,
        b => return Err(format!("unknown backend `{b}` (expected cpu or gpu)")),
    };
    if gpu && kind == Kind::GlossyReference {
        return Err(
            "--backend gpu does not apply to --method glossy-reference (its photon tracing runs on the CPU)".into()
        );
    }
    for id in &a.given {
        if let Some(kinds) = applies_to(id, gpu, a.primary_beams()) {
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
    let shading = match a.shading.as_str() {
        "fraction" => Shading::Fraction,
        "exact" => Shading::Exact,
        s => return Err(format!("unknown --shading `{s}` (expected exact or fraction)")),
    };
    let occluders = match a.occluders.as_str() {
        "auto" => Occluders::Auto,
        "split" => Occluders::Split,
        "edges" => Occluders::Edges,
        o => return Err(format!("unknown --occluders `{o}` (expected auto, split or edges)")),
    };
    let degree = match a.degree.as_str() {
        "s1" => Degree::S1,
        "s3" => Degree::S3,
        d => return Err(format!("unknown --degree `{d}` (expected s1 or s3)")),
    };
    let volume = match a.volume.as_str() {
        "exact" => VolumeMethod::Exact,
        "tessellated" => VolumeMethod::Tessellated,
        v => return Err(format!("unknown --volume `{v}` (expected exact or tessellated)")),
    };
    // The nonlinear tracer sizes beam regions from 4 texels up to `--texels`.
    range("texels", a.texels, 4, 4096)?;
    range("bounces", a.bounces, 1, 16)?;
    range("caustic_strata", a.caustic_strata, 0, beam_render::nonlinear::MAX_CAUSTIC_STRATA)?;
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
    crate::output::check_render_outputs(&a.out, a.stats.as_deref())?;
    check_scene_path(&a.scene)?;
    let mut scene = match a.smesh {
        Some(n) => scene::builtin_with_smesh(&a.scene, n).map_err(|e| e.to_string())?,
        None => scene::load_with(&a.scene, &scene::LoadOptions { allow_outside_paths: a.allow_outside_paths })
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
    if let Some(e) = &a.env {
        scene.environment = environment(e)?;
    }
    crate::unused::warn(&scene, kind, gpu && a.second_order());
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
    let region = crate::region::parse(a.tile.as_deref(), a.crop.as_deref(), width, height)?;
    let memory = estimate(kind, width, height, scene.triangles.len(), a.photons);
    crate::limits::admit(&format!("a {width}×{height} {} render", kind.name()), memory, quiet)?;
    let options = RenderOptions {
        method: if kind == Kind::Ray { Method::Ray } else { Method::Beam },
        shading,
        spp: a.spp,
        primary_spp: a.primary_spp,
        // On the GPU every shadow beam is traced to the end.
        primary_beams: a.primary_beams(),
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
        a.primary_beams(),
        a.occluders,
        a.exact,
        a.volume,
        a.linear_gather,
        a.subdivide,
        a.second_order(),
        a.photon_kernel,
        a.photons,
        width,
        height,
        a.exposure.to_bits(),
        a.frame,
        a.allow_outside_paths,
        // Only when given, so that the fingerprints of renders without it stay as they were.
        a.env.as_ref().map(|e| format!("|env {e}")).unwrap_or_default(),
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
