//! Every method on every scene (issue 18): each built-in scene × each method × each backend renders
//! at 32² to a finite image that is not black, or fails with an error that says the pair is not
//! applicable — never a wgpu validation error, another error, or a panic. The methods are
//! dispatched to the same library functions `beam render` calls (beam-cli/src/render.rs), with
//! tiny photon, sample and texel counts so that the whole matrix stays within CI's time. The GPU
//! column runs on whatever adapter wgpu finds (Mesa lavapipe in CI) and, as the GPU conformance
//! properties do, is skipped, saying why, when there is none (`BEAM_REQUIRE_GPU=1` makes that a
//! failure). Also: the nonlinear renderer takes any `texels` without panicking.

use beam_cpu::glossy::{render_glossy, render_glossy_reference, render_glossy_with};
use beam_cpu::nonlinear::{CpuBeams, render_smooth_reference_with};
use beam_cpu::render::{render, render_queries};
use beam_gpu::Gpu;
use beam_gpu::glossy::GpuGather;
use beam_gpu::nonlinear::GpuBeams;
use beam_gpu::queries::GpuQueries;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::glossy::{GlossyOptions, LightVolumes};
use beam_render::image::Image;
use beam_render::nonlinear::{BeamRenderer, Degree};
use beam_render::nonlinear::{NonlinearOptions, render_nonlinear_with};
use beam_render::options::{Method, RenderOptions};
use beam_scene::scene::{self, BUILTIN, Scene};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

/// Image side of every cell.
const SIZE: u32 = 32;
/// Shadow rays per area light (`ray`, and the GPU's nonlinear shading).
const SPP: u32 = 4;
/// Photons per light of the references.
const PHOTONS: u64 = 2_000;
/// Most texels per side of a nonlinear beam.
const TEXELS: u32 = 8;

/// The methods of `beam render --method`, and `beam` with `--primary-beams`.
const METHODS: [&str; 7] =
    ["beam", "primary-beams", "ray", "nonlinear", "nonlinear-reference", "glossy", "glossy-reference"];

/// The start of every error that means "this pair does not apply" (rather than a failure).
const NOT_APPLICABLE: &str = "not applicable";

/// The shading options of the `beam`, `ray` and nonlinear methods at [`SIZE`]².
fn shading(method: Method, primary_beams: bool) -> RenderOptions {
    RenderOptions { method, primary_beams, spp: SPP, ..RenderOptions::exact(SIZE, SIZE) }
}

/// Render `scene` by `method` on the CPU, or on `gpu` when given, as `beam render` does.
fn render_cell(scene: &Scene, method: &str, gpu: Option<&Gpu>) -> Result<Image, String> {
    let mut gpu_beams = match (gpu, method.starts_with("nonlinear")) {
        (Some(g), true) => Some(GpuBeams::new(g, scene).map_err(|e| e.to_string())?.with_light_samples(SPP)),
        _ => None,
    };
    let mut cpu = CpuBeams;
    let renderer: &mut dyn BeamRenderer = match &mut gpu_beams {
        Some(g) => g,
        None => &mut cpu,
    };
    let glossy = GlossyOptions { subdivide: 1, ..GlossyOptions::new(SIZE, SIZE) };
    match (method, gpu) {
        ("glossy-reference", Some(_)) => Err(format!("{NOT_APPLICABLE}: `{method}` has no GPU backend")),
        ("beam" | "primary-beams" | "ray", Some(g)) => {
            let queries = GpuQueries::new(g, scene).map_err(|e| e.to_string())?;
            let method_of = if method == "ray" { Method::Ray } else { Method::Beam };
            let options = shading(method_of, method == "primary-beams");
            Ok(render_queries(scene, &options, &queries, || {}).map_err(|e| e.to_string())?.0)
        }
        ("beam", None) => Ok(render(scene, &shading(Method::Beam, false), || {}).0),
        ("primary-beams", None) => Ok(render(scene, &shading(Method::Beam, true), || {}).0),
        ("ray", None) => Ok(render(scene, &shading(Method::Ray, false), || {}).0),
        ("nonlinear", _) => {
            let options = NonlinearOptions {
                degree: Degree::S3,
                texels: TEXELS,
                bounces: 2,
                caustic_strata: 1,
                shading: shading(Method::Beam, false),
            };
            Ok(render_nonlinear_with(scene, &options, renderer, &CpuBeams).map_err(|e| e.to_string())?.0)
        }
        ("nonlinear-reference", _) => {
            render_smooth_reference_with(scene, &shading(Method::Beam, false), PHOTONS, renderer)
                .map_err(|e| e.to_string())
        }
        ("glossy", None) => Ok(render_glossy(scene, &glossy).map_err(|e| e.to_string())?.0),
        ("glossy", Some(g)) => {
            let gather = GpuGather::new(g, scene).map_err(|e| e.to_string())?;
            let run = |v: &LightVolumes, points: &[(Vec3, Vec3)]| {
                gather.gather(g, v, points, &glossy).map_err(BackendError::from)
            };
            Ok(render_glossy_with(scene, &glossy, &CpuBeams, &run).map_err(|e| e.to_string())?.0)
        }
        ("glossy-reference", None) => render_glossy_reference(scene, SIZE, SIZE, PHOTONS, 1).map_err(|e| e.to_string()),
        _ => Err(format!("unknown method `{method}`")),
    }
}

/// What one cell came to: `Ok(note)` (rendered, or not applicable), `Err(why it failed)`.
fn check_cell(scene: &Scene, method: &str, gpu: Option<&Gpu>) -> Result<String, String> {
    let result = catch_unwind(AssertUnwindSafe(|| render_cell(scene, method, gpu)));
    match result {
        Err(panic) => {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_string()))
                .unwrap_or_default();
            Err(format!("panicked: {message}"))
        }
        Ok(Err(e)) if e.starts_with(NOT_APPLICABLE) => Ok(e),
        Ok(Err(e)) => Err(format!("error: {e}")),
        Ok(Ok(image)) => {
            if image.width != SIZE || image.height != SIZE {
                return Err(format!("{}×{} image, not {SIZE}²", image.width, image.height));
            }
            if let Some(i) = image.pixels.iter().position(|p| !p.is_finite() || p.min_element() < 0.0) {
                return Err(format!("pixel {i} is {}", image.pixels[i]));
            }
            let peak = image.pixels.iter().map(|p| p.max_element()).fold(0.0f32, f32::max);
            if peak <= 0.0 {
                return Err("black image".into());
            }
            let mean = image.pixels.iter().map(|p| p.element_sum() / 3.0).sum::<f32>() / image.pixels.len() as f32;
            Ok(format!("mean {mean:.3}, peak {peak:.2}"))
        }
    }
}

/// Run every (scene, method) cell on the CPU, or on `gpu`, and fail listing every failed cell.
fn run_matrix(gpu: Option<&Gpu>) {
    let backend = if gpu.is_some() { "gpu" } else { "cpu" };
    let start = Instant::now();
    let mut failures = Vec::new();
    for name in BUILTIN {
        let scene = match scene::builtin(name) {
            Ok(s) => s,
            Err(e) => {
                failures.push(format!("{name}: does not load: {e}"));
                continue;
            }
        };
        for method in METHODS {
            let t = Instant::now();
            let outcome = check_cell(&scene, method, gpu);
            let seconds = t.elapsed().as_secs_f64();
            match &outcome {
                Ok(note) => println!("{name:>22} {method:>20} {backend}: ok ({note}) {seconds:.2} s"),
                Err(e) => println!("{name:>22} {method:>20} {backend}: FAILED {e} {seconds:.2} s"),
            }
            if let Err(e) = outcome {
                failures.push(format!("{name} × {method} × {backend}: {e}"));
            }
        }
    }
    println!("{backend} matrix: {:.1} s", start.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{} cells failed:\n{}", failures.len(), failures.join("\n"));
}

/// The adapter, or `None` after printing why the GPU part is skipped (a failure instead when
/// `BEAM_REQUIRE_GPU=1`).
fn adapter() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) => {
            assert!(!beam_conformance::gpu_required(), "BEAM_REQUIRE_GPU=1 but {e}");
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "SKIPPED: {e}");
            None
        }
    }
}

#[test]
fn every_method_on_every_scene_cpu() {
    run_matrix(None);
}

#[test]
fn every_method_on_every_scene_gpu() {
    if let Some(gpu) = adapter() {
        run_matrix(Some(&gpu));
    }
}

/// `texels` per beam side below the 4 a beam's region normally has at least, and outside the range
/// the library takes (0, 1: clamped to 2), on a scene with mirrors (issue 18: 2 and 3 panicked).
fn any_texels_render(gpu: Option<&Gpu>) {
    let scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    for texels in [0, 1, 2, 3, 5] {
        let mut gpu_beams = gpu.map(|g| GpuBeams::new(g, &scene).expect("the GPU renderer"));
        let mut cpu = CpuBeams;
        let renderer: &mut dyn BeamRenderer = match &mut gpu_beams {
            Some(g) => g,
            None => &mut cpu,
        };
        let options = NonlinearOptions {
            degree: Degree::S1,
            texels,
            bounces: 2,
            caustic_strata: 1,
            shading: shading(Method::Beam, false),
        };
        let (image, stats) = render_nonlinear_with(&scene, &options, renderer, &CpuBeams)
            .unwrap_or_else(|e| panic!("texels {texels}: {e}"));
        assert!(image.pixels.iter().all(|p| p.is_finite()), "texels {texels}: non-finite pixels");
        assert!(stats.texels_shaded > 0, "texels {texels}: no beam texel hit the scene");
        assert!(stats.triangles_per_beam >= 0.0);
    }
}

#[test]
fn nonlinear_takes_any_texels_cpu() {
    any_texels_render(None);
}

#[test]
fn nonlinear_takes_any_texels_gpu() {
    if let Some(gpu) = adapter() {
        any_texels_render(Some(&gpu));
    }
}
