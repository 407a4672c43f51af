//! The wavefront frame ([`render_queries`]) against the CPU renderer ([`render`]) with primary rays
//! and exact beams: the same image for both methods and shadings, crops, point lights, mirrors and
//! glass, a sky, and backends that give up on beams or answer wrongly.

use beam_bvh::Hit;
use beam_cpu::nonlinear::CpuBeams;
use beam_cpu::render::{RenderStats, difference, render, render_queries};
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::image::Image;
use beam_render::options::{Method, RenderOptions, Shading};
use beam_render::queries::{BeamQueries, LightPolygon, LightQuery, LightSeen, RayQueries};
use beam_scene::region::PixelRect;
use beam_scene::scene::{Environment, EnvironmentMap, Scene, builtin};
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

/// Primary rays, exact beams, `spp` shadow rays for `ray`, `primary_spp` camera rays a pixel.
fn options(method: Method, shading: Shading, size: u32, primary_spp: u32) -> RenderOptions {
    RenderOptions {
        method,
        shading,
        spp: 16,
        primary_spp,
        primary_beams: false,
        exact: true,
        ..RenderOptions::exact(size, size)
    }
}

/// The largest difference of a channel relative to the larger of the two values (at least 1e-3).
fn max_relative(a: &Image, b: &Image) -> f32 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs() / p[k].abs().max(q[k].abs()).max(1e-3)))
        .fold(0.0, f32::max)
}

/// Both renders of `scene` with `options`; asserts the wavefront's image within `min_psnr` dB of
/// the CPU's (and the same size), and returns both stats.
fn same_image(name: &str, scene: &Scene, options: &RenderOptions, min_psnr: f64) -> (RenderStats, RenderStats) {
    let rows = AtomicU32::new(0);
    let (wave, wave_stats) = render_queries(scene, options, &CpuBeams, || {
        rows.fetch_add(1, Ordering::Relaxed);
    })
    .unwrap();
    let (cpu, cpu_stats) = render(scene, options, || {});
    assert_eq!(rows.load(Ordering::Relaxed), cpu.height, "{name}: a row_done a row");
    let d = difference(&wave, &cpu).unwrap();
    let lit = wave.pixels.iter().filter(|p| p.max_element() > 0.0).count();
    println!(
        "{name} {:?} {:?}: PSNR {:.1} dB, max relative {:.2e}, {lit} lit pixels",
        options.method,
        options.shading,
        d.psnr,
        max_relative(&wave, &cpu)
    );
    assert!(lit > wave.pixels.len() / 4, "{name}: the image is mostly dark");
    assert!(d.psnr >= min_psnr, "{name}: PSNR {} dB", d.psnr);
    // `render` traces a crop's whole shading tiles.
    if options.region.is_some() {
        return (wave_stats, cpu_stats);
    }
    assert_eq!(wave_stats.camera_rays, cpu_stats.camera_rays, "{name}: the same camera, mirror and glass rays");
    assert_eq!(wave_stats.environment_rays, cpu_stats.environment_rays, "{name}: the same sky rays");
    if options.method == Method::Ray {
        assert_eq!(wave_stats.shadow_rays, cpu_stats.shadow_rays, "{name}: the same shadow rays");
    }
    (wave_stats, cpu_stats)
}

/// `name` under a uniform sky.
fn with_sky(name: &str) -> Scene {
    let mut scene = builtin(name).unwrap();
    scene.environment = Environment::Constant(Vec3::new(0.3, 0.4, 0.5));
    scene
}

#[test]
fn beams_give_the_cpu_image() {
    for name in ["cornell", "mirror-glass", "cornell-point"] {
        let scene = builtin(name).unwrap();
        for shading in [Shading::Exact, Shading::Fraction] {
            let (wave, cpu) = same_image(name, &scene, &options(Method::Beam, shading, 48, 1), 60.0);
            assert!(wave.shadow_beams > 0 || name == "cornell-point", "{name}: no shadow beam");
            assert_eq!(wave.overflow_beams, 0);
            assert_eq!((wave.method.as_str(), wave.width, wave.triangles), ("beam", 48, cpu.triangles));
        }
    }
}

#[test]
fn rays_give_the_cpu_image_sample_for_sample() {
    for name in ["cornell", "mirror-glass", "cornell-point"] {
        let scene = builtin(name).unwrap();
        for shading in [Shading::Exact, Shading::Fraction] {
            let (wave, _) = same_image(name, &scene, &options(Method::Ray, shading, 32, 4), 80.0);
            assert!(wave.shadow_rays > 0 && wave.spp == 16);
        }
    }
}

#[test]
fn a_uniform_sky_gives_the_cpu_image() {
    // As six lights with beams; by cosine-weighted rays with `ray`.
    let scene = with_sky("mirror-glass");
    let (wave, cpu) = same_image("mirror-glass + sky", &scene, &options(Method::Beam, Shading::Exact, 32, 1), 60.0);
    assert_eq!(wave.environment_lights, 6);
    assert_eq!(wave.environment_lights, cpu.environment_lights);
    let (wave, _) = same_image("mirror-glass + sky", &scene, &options(Method::Ray, Shading::Exact, 32, 4), 80.0);
    assert!(wave.environment_rays > 0 && wave.exact_pixel_share < 1.0);
}

#[test]
fn a_sky_map_is_sampled_from_the_cpu_streams() {
    // A map is sampled by rays under `beam` too, from the shade points' random streams.
    let texels =
        (0..32 * 16).map(|i| Vec3::new(0.2 + (i % 32) as f32 / 40.0, 0.3, 0.2 + (i / 32) as f32 / 20.0)).collect();
    let mut scene = builtin("mirror-glass").unwrap();
    scene.environment = Environment::Map(Arc::new(EnvironmentMap::new(32, 16, texels).unwrap()));
    let (wave, cpu) = same_image("mirror-glass + map", &scene, &options(Method::Beam, Shading::Exact, 32, 4), 60.0);
    assert!(wave.environment_rays > 0);
    assert_eq!(wave.max_error_bound, cpu.max_error_bound);
}

#[test]
fn a_region_is_its_part_of_the_frame() {
    let scene = builtin("mirror-glass").unwrap();
    let region = Some(PixelRect { x0: 5, y0: 9, x1: 29, y1: 40 });
    for method in [Method::Beam, Method::Ray] {
        let crop = RenderOptions { region, ..options(method, Shading::Exact, 48, 4) };
        same_image("mirror-glass crop", &scene, &crop, 60.0);
        let (part, _) = render_queries(&scene, &crop, &CpuBeams, || {}).unwrap();
        let (whole, _) = render_queries(&scene, &options(method, Shading::Exact, 48, 4), &CpuBeams, || {}).unwrap();
        assert_eq!((part.width, part.height), (24, 31));
        for y in 0..31 {
            for x in 0..24 {
                assert_eq!(part.pixels[y * 24 + x], whole.pixels[(y + 9) * 48 + x + 5], "pixel ({x}, {y})");
            }
        }
    }
}

/// The CPU's queries, but every other shadow beam of a batch given up (`None`); or, with `short`,
/// one answer too few to each batch of closest hits.
struct Flaky {
    short: bool,
}

impl RayQueries for Flaky {
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        let mut hits = CpuBeams.closest_hits(scene, rays)?;
        if self.short {
            hits.pop();
        }
        Ok(hits)
    }

    fn any_hits(&self, scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        CpuBeams.any_hits(scene, segments)
    }
}

impl BeamQueries for Flaky {
    fn light_visibility(
        &self,
        scene: &Scene,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<Option<LightSeen>>, BackendError> {
        let mut seen = CpuBeams.light_visibility(scene, lights, queries)?;
        seen.iter_mut().skip(1).step_by(2).for_each(|s| *s = None);
        Ok(seen)
    }
}

#[test]
fn beams_a_backend_gives_up_are_traced_by_the_host() {
    let scene = with_sky("cornell");
    for shading in [Shading::Exact, Shading::Fraction] {
        let opts = options(Method::Beam, shading, 32, 1);
        let (flaky, stats) = render_queries(&scene, &opts, &Flaky { short: false }, || {}).unwrap();
        let (cpu, all) = render_queries(&scene, &opts, &CpuBeams, || {}).unwrap();
        assert_eq!(flaky, cpu, "the host's beams are the CPU backend's");
        assert_eq!(stats.shadow_beams, all.shadow_beams);
        assert!(stats.overflow_beams > 0 && stats.overflow_beams <= stats.shadow_beams.div_ceil(2) + 1, "{stats:?}");
        assert_eq!(all.overflow_beams, 0);
        assert!(difference(&flaky, &render(&scene, &opts, || {}).0).unwrap().psnr >= 60.0);
    }
}

#[test]
fn a_backend_that_answers_wrongly_is_an_error() {
    let scene = builtin("cornell").unwrap();
    let result = render_queries(&scene, &options(Method::Beam, Shading::Exact, 16, 1), &Flaky { short: true }, || {});
    let message = result.expect_err("one hit too few is an error").to_string();
    assert!(message.contains("answers to"), "{message}");
    // A query naming a light the batch lacks.
    let q = LightQuery { p: Vec3::ZERO, n: Vec3::Y, light: 3, clip_above: true };
    assert!(CpuBeams.light_visibility(&scene, &[], &[q]).is_err());
}

/// Eye beams (exact box-filtered coverage, each fragment shaded at its centroid, a mirror or glass
/// fragment by one ray through its centroid) against the CPU renderer's eye beams, which shade a
/// point light's lit fragments by their visible pieces (001 §4.2) and trace mirror and glass
/// pixels by primary rays: the same image but at point-light shadow edges and on curved mirrors.
#[test]
fn eye_beams_give_the_cpu_eye_beam_image() {
    for (name, min_psnr) in [("cornell", 50.0), ("mirror-glass", 28.0), ("cornell-point", 30.0)] {
        let scene = builtin(name).unwrap();
        let opts = RenderOptions { primary_beams: true, ..options(Method::Beam, Shading::Exact, 48, 1) };
        let (wave, stats) = render_queries(&scene, &opts, &CpuBeams, || {}).unwrap();
        let (cpu, _) = render(&scene, &opts, || {});
        let d = difference(&wave, &cpu).unwrap();
        println!("{name} eye beams: PSNR {:.1} dB, {} fragments", d.psnr, stats.fragments);
        assert!(d.psnr >= min_psnr, "{name}: PSNR {:.1} dB", d.psnr);
        assert!(stats.fragments >= 48 * 48 && stats.overflow_pixels == 0);
    }
}
