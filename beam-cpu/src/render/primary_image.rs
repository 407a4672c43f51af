//! Exact primary visibility as an image (001 §3): the eye beams' visible pieces rasterized with
//! exact box-filtered pixel coverage, each fragment shaded by a caller's function — the ground truth
//! that primary rays with N samples per pixel converge to. Under a budget, a region whose eye beam
//! would cost more than N rays a pixel (sub-pixel triangles, [`super::eye_budget`]) is sampled by
//! those rays instead.

use super::cut_outs::CutOuts;
use super::eye_budget::{grid_hits, trace_budget};
use super::eye_regions::{EyeBeam, EyeStats, Fragment, Region, paste, region_fragments, regions};
use super::primary_beam::nearest_first;
use super::renderer::stratified;
use super::shadow_beam::BeamStats;
use beam_math::glam::Vec3;
use beam_render::image::Image;
use beam_scene::scene::{Camera, Scene};
use rand::SeedableRng;
use rand_pcg::Pcg32;
use rayon::prelude::*;
use std::time::Instant;

/// How [`primary_image`] sees each region of the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visibility {
    /// Eye beams everywhere: exact box-filtered coverage (except where a region sees a cut-out
    /// triangle: [`CUT_OUT_RAYS`] rays a pixel there).
    Exact,
    /// Eye beams where they cost at most half of `rays` stratified primary rays a pixel
    /// ([`pixel_samples`]), those rays elsewhere: exact where the triangles are large enough on
    /// screen for beams to pay. A region's cost is predicted from a grid of rays through it, and its
    /// eye beam stops once its work passes the budget (`eye_budget.rs`). Regions that see a cut-out
    /// triangle go to rays too.
    Budget {
        /// Rays a pixel of the regions left to rays (a square number is used whole: `⌊√rays⌋²`).
        rays: u32,
    },
}

/// The `k × k` stratified jittered sample positions in pixel `(x, y)`, in image coordinates, from
/// a random stream seeded by the pixel: every tracer that uses them traces the same rays.
pub fn pixel_samples(x: u32, y: u32, k: u32) -> impl Iterator<Item = (f32, f32)> {
    let seed = (u64::from(y) << 32 | u64::from(x)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let mut rng = Pcg32::seed_from_u64(seed);
    (0..k * k).map(move |i| {
        let (jx, jy) = stratified(i, k, &mut rng);
        (x as f32 + jx, y as f32 + jy)
    })
}

/// What the eye beams of [`primary_image`] did.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct PrimaryStats {
    /// Wall time, seconds.
    pub seconds: f64,
    /// Distinct triangles seen.
    pub visible_triangles: u64,
    /// Hit pieces produced by the eye beams (001's "hit beams").
    pub hit_beams: u64,
    /// BVH nodes tested against the eye beams.
    pub bvh_steps: u64,
    /// Triangles set up against the eye beams.
    pub triangle_tests: u64,
    /// Eye-beam–triangle splits.
    pub intersections: u64,
    /// Pieces the eye beams ended with (each sees one triangle or the background).
    pub pieces: u64,
    /// Seconds spent tracing the eye beams, summed over threads (the rest of [`Self::seconds`]
    /// is exact coverage and shading).
    pub trace_seconds: f64,
    /// `hit_beams / visible_triangles` (001 Fig. 5).
    pub hit_beams_per_visible_triangle: f64,
    /// Fragments shaded (a visible piece of a triangle within a pixel).
    pub fragments: u64,
    /// Largest `|1 − Σ coverage|` of a pixel, background included (exact coverage sums to one).
    pub coverage_error: f64,
    /// Pixels sampled by rays under [`Visibility::Budget`] (the rest are exact).
    pub ray_pixels: u64,
    /// Primary rays traced under [`Visibility::Budget`].
    pub rays: u64,
    /// Eye beams stopped at their budget under [`Visibility::Budget`] (their regions went to rays).
    pub over_budget_regions: u64,
    /// Regions whose view meets a cut-out triangle (`alphaMode` `MASK` or `BLEND`): they went to
    /// rays, which see through it ([`Scene::blended_hits`]); [`CUT_OUT_RAYS`] a pixel under
    /// [`Visibility::Exact`].
    pub cut_out_regions: u64,
}

/// Rays a pixel of the regions that may see a cut-out under [`Visibility::Exact`]: 2 × 2, as many
/// as the renderer's ray regions trace in a pixel an edge crosses.
pub const CUT_OUT_RAYS: u32 = 4;

/// What a region returns.
struct Part {
    region: Region,
    pixels: Vec<Vec3>,
    eye: EyeStats,
    fragments: u64,
    /// Largest coverage error of its pixels.
    error: f64,
    /// The triangles it saw.
    seen: Vec<bool>,
    /// Rays traced instead of its eye beam (0 when exact).
    rays: u64,
    /// Whether it went to rays because it may see a cut-out.
    cut_out: bool,
}

/// The image `camera` sees of `scene` by primary visibility as `visibility` says: by eye beams,
/// each pixel is the coverage-weighted sum over its fragments of `shade(prim, q, d)` — triangle
/// `prim` seen at point `q` (the fragment's centroid) along the unit direction `d` — and the
/// scene's environment where the background shows (its radiance along the direction through the
/// background fragment's centroid: exact for a constant environment); by rays, the mean over the
/// pixel's samples of the same. Regions of [`super::region_side`]² pixels run in parallel;
/// `pixels_done(n)` is called after each with its pixel count (for a progress bar).
pub fn primary_image(
    scene: &Scene,
    camera: &Camera,
    visibility: Visibility,
    shade: impl Fn(u32, Vec3, Vec3) -> Vec3 + Sync,
    pixels_done: impl Fn(u64) + Sync,
) -> (Image, PrimaryStats) {
    let start = Instant::now();
    let cut_outs = CutOuts::of(scene);
    let parts: Vec<Part> = regions(camera.width, camera.height)
        .into_par_iter()
        .map(|region| {
            let cut_out = cut_outs.is_some_and(|c| c.may_show(camera, region));
            let (budget, rays, seeds) = match visibility {
                Visibility::Exact => (Some(f64::INFINITY), CUT_OUT_RAYS, None),
                // A region that may see a cut-out goes to rays: no grid of rays to predict its beam.
                Visibility::Budget { rays } if cut_out => (None, rays, None),
                Visibility::Budget { rays } => {
                    // The grid of rays that predicts the beam's cost also seeds it.
                    let hits = grid_hits(scene, camera, region);
                    (trace_budget(scene, camera, (region, &hits), (rays, rays)), rays, Some(nearest_first(hits)))
                }
            };
            let part = match budget.filter(|_| !cut_out) {
                None => Part { cut_out, ..ray_part(scene, camera, region, rays, &shade) },
                Some(budget) => {
                    let eye = eye_part(scene, camera, region, (budget, seeds.as_deref()), &shade);
                    if eye.eye.over_budget > 0 {
                        // The work spent counts; the pixels come from rays.
                        Part { eye: eye.eye, ..ray_part(scene, camera, region, rays, &shade) }
                    } else {
                        eye
                    }
                }
            };
            pixels_done(region.len() as u64);
            part
        })
        .collect();
    let mut image = Image::new(camera.width, camera.height);
    let mut stats = PrimaryStats::default();
    let mut visible = vec![false; scene.triangles.len()];
    let mut beams = BeamStats::default();
    for part in parts {
        paste(part.region, &part.pixels, &mut image);
        beams += part.eye.primary;
        stats.pieces += part.eye.pieces;
        stats.trace_seconds += part.eye.trace_seconds;
        stats.fragments += part.fragments;
        stats.coverage_error = stats.coverage_error.max(part.error);
        visible.iter_mut().zip(part.seen).for_each(|(v, s)| *v |= s);
        if part.rays > 0 {
            stats.ray_pixels += part.region.len() as u64;
            stats.rays += part.rays;
        }
        stats.over_budget_regions += part.eye.over_budget;
        stats.cut_out_regions += u64::from(part.cut_out);
    }
    stats.visible_triangles = visible.iter().filter(|&&v| v).count() as u64;
    stats.hit_beams = beams.hit_beams;
    stats.bvh_steps = beams.bvh_steps;
    stats.intersections = beams.intersections;
    stats.triangle_tests = beams.triangle_tests;
    stats.hit_beams_per_visible_triangle = beams.hit_beams as f64 / stats.visible_triangles.max(1) as f64;
    stats.seconds = start.elapsed().as_secs_f64();
    (image, stats)
}

/// `region` by its eye beam, which may take `budget` thread-seconds (past them, the part's pixels
/// are empty and its `eye.over_budget` is 1), split first by `seeds` ([`EyeBeam::seeds`]).
/// Cut-outs are opaque to it: regions that may see one go to [`ray_part`] first.
fn eye_part(
    scene: &Scene,
    camera: &Camera,
    region: Region,
    (budget, seeds): (f64, Option<&[u32]>),
    shade: &(impl Fn(u32, Vec3, Vec3) -> Vec3 + Sync),
) -> Part {
    let mut pixels = vec![Vec3::ZERO; region.len()];
    let mut coverage = vec![0.0f32; region.len()];
    let mut seen = vec![false; scene.triangles.len()];
    let mut fragments = 0u64;
    let mut eye = EyeStats::default();
    let beam = EyeBeam { budget, seeds, ..EyeBeam::exact(region) };
    region_fragments(scene, camera, beam, &mut eye, &mut seen, |x, y, cov, f| {
        let i = region.index(x, y);
        coverage[i] += cov;
        match f {
            Fragment::Surface { prim, q, d } => {
                fragments += 1;
                pixels[i] += cov * shade(prim, q, d);
            }
            Fragment::Background { d } => pixels[i] += cov * scene.environment.radiance(d),
            Fragment::Lit { .. } | Fragment::Covered => {}
        }
    });
    let error = coverage.iter().fold(0.0f64, |m, &c| m.max(f64::from((1.0 - c).abs())));
    Part { region, pixels, eye, fragments, error, seen, rays: 0, cut_out: false }
}

/// `region` by `⌊√rays⌋²` stratified primary rays a pixel ([`pixel_samples`]), `BLEND` surfaces
/// blended ([`Scene::blended_hits`]).
fn ray_part(
    scene: &Scene,
    camera: &Camera,
    region: Region,
    rays: u32,
    shade: &(impl Fn(u32, Vec3, Vec3) -> Vec3 + Sync),
) -> Part {
    let k = ((rays.max(1) as f32).sqrt() as u32).max(1);
    let frame = camera.frame();
    let mut pixels = vec![Vec3::ZERO; region.len()];
    let mut seen = vec![false; scene.triangles.len()];
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            let mut sum = Vec3::ZERO;
            for (sx, sy) in pixel_samples(x, y, k) {
                let ray = camera.ray(&frame, sx, sy);
                let d = ray.direction.normalize();
                let beyond = scene.blended_hits(ray, f32::INFINITY, |hit, share| {
                    seen[hit.prim as usize] = true;
                    sum += share * shade(hit.prim, ray.at(hit.t), d);
                });
                if beyond > 0.0 {
                    sum += beyond * scene.environment.radiance(d);
                }
            }
            pixels[region.index(x, y)] = sum / (k * k) as f32;
        }
    }
    let rays = region.len() as u64 * u64::from(k * k);
    Part { region, pixels, eye: EyeStats::default(), fragments: 0, error: 0.0, seen, rays, cut_out: false }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_scene::scene::builtin;

    /// On the closed Cornell box every pixel is covered exactly once, and with a constant shade the
    /// image is that constant up to the coverage error; every triangle facing the camera is seen.
    #[test]
    fn closed_room_covers_every_pixel_once() {
        let scene = builtin("cornell").unwrap();
        let (position, target) = (Vec3::new(278.0, 273.0, 100.0), Vec3::new(278.0, 273.0, 555.0));
        let camera = Camera { position, target, fov_y: 90.0, ..scene.camera.with_size(48, 32) };
        let (image, stats) = primary_image(&scene, &camera, Visibility::Exact, |_, _, _| Vec3::ONE, |_| {});
        assert!(stats.coverage_error < 1e-3, "coverage error {}", stats.coverage_error);
        for (i, p) in image.pixels.iter().enumerate() {
            assert!((p.x - 1.0).abs() < 1e-3, "pixel {i}: {p}");
        }
        assert!(stats.visible_triangles >= 10 && stats.hit_beams >= stats.visible_triangles);
        assert!(stats.fragments >= 48 * 32);
        // A shade of the primitive's index shows which triangle covers each pixel's centre.
        let (ids, _) = primary_image(&scene, &camera, Visibility::Exact, |prim, _, _| Vec3::splat(prim as f32), |_| {});
        let frame = camera.frame();
        let pure = ids.pixels.iter().enumerate().filter(|&(i, p)| {
            let hit = scene.wide.closest_hit(camera.pixel_ray(&frame, i), f32::INFINITY).unwrap();
            (p.x - hit.prim as f32).abs() < 1e-3
        });
        assert!(pure.count() > 48 * 32 * 3 / 4, "most pixels lie inside one triangle, the one rays see");
    }

    /// A wall of two big triangles filling the view, and before it, within one region, a sphere of
    /// 20,000 triangles of about a hundredth of a pixel each. Under a budget of 16 rays a pixel the
    /// sphere's region goes to rays and the others stay exact: their pixels are the exact image's,
    /// bit for bit, and the rays' region is within sampling error of it.
    #[test]
    fn a_budget_leaves_sub_pixel_triangles_to_rays_and_the_rest_exact() {
        use beam_math::Triangle;
        use beam_scene::scene::Material;
        let wall = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [Triangle::new(a, b, c), Triangle::new(a, c, d)];
        let mut tris: Vec<(Triangle, u32)> = wall(
            Vec3::new(-10.0, -10.0, 10.0),
            Vec3::new(10.0, -10.0, 10.0),
            Vec3::new(10.0, 10.0, 10.0),
            Vec3::new(-10.0, 10.0, 10.0),
        )
        .into_iter()
        .map(|t| (t, 0))
        .collect();
        let sphere = beam_scene::mesh::sphere(Vec3::new(-1.6, 1.6, 5.0), 0.55, 100, 100);
        tris.extend(sphere.triangles().into_iter().map(|t| (t, 1)));
        let materials = vec![
            Material::Diffuse { albedo: Vec3::splat(0.5) },
            Material::Diffuse { albedo: Vec3::new(0.9, 0.2, 0.1) },
        ];
        let camera = Camera { position: Vec3::ZERO, target: Vec3::Z, up: Vec3::Y, fov_y: 60.0, width: 64, height: 64 };
        let scene = Scene::new("budget".into(), tris, materials, Vec::new(), camera);
        let shade = |prim: u32, _: Vec3, _: Vec3| if prim < 2 { Vec3::splat(0.5) } else { Vec3::new(0.9, 0.2, 0.1) };
        let (exact, es) = primary_image(&scene, &camera, Visibility::Exact, shade, |_| {});
        let (budget, bs) = primary_image(&scene, &camera, Visibility::Budget { rays: 16 }, shade, |_| {});
        assert_eq!(es.ray_pixels, 0);
        let side = super::super::region_side(64, 64);
        assert!(bs.ray_pixels > 0 && bs.ray_pixels < 64 * 64, "{} pixels by rays", bs.ray_pixels);
        assert_eq!(bs.rays, 16 * bs.ray_pixels);
        let mut sampled = 0;
        for region in regions(64, 64) {
            let px = |img: &Image| -> Vec<Vec3> {
                (region.y0..region.y1)
                    .flat_map(|y| (region.x0..region.x1).map(move |x| (x, y)))
                    .map(|(x, y)| img.pixels[(y * 64 + x) as usize])
                    .collect()
            };
            let (a, b) = (px(&exact), px(&budget));
            if a == b {
                continue;
            }
            sampled += 1;
            let mse = a.iter().zip(&b).map(|(p, q)| (*p - *q).length_squared()).sum::<f32>() / a.len() as f32;
            assert!(mse.sqrt() < 0.05, "RMSE {} in {region:?}", mse.sqrt());
        }
        // The sphere lies within one region: only that one was sampled.
        assert_eq!((sampled, bs.ray_pixels), (1, u64::from(side * side)));
    }
}
