//! Exact primary visibility as an image (001 §3): the eye beams' visible pieces rasterized with
//! exact box-filtered pixel coverage, each fragment shaded by a caller's function — the ground truth
//! that primary rays with N samples per pixel converge to.

use super::eye_regions::{EyeStats, Fragment, Region, paste, region_fragments, regions};
use super::image::Image;
use super::shadow_beam::BeamStats;
use beam_math::glam::Vec3;
use beam_scene::scene::{Camera, Scene};
use rayon::prelude::*;
use std::time::Instant;

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
}

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
}

/// The image `camera` sees of `scene` by exact primary visibility: each pixel is the
/// coverage-weighted sum over its fragments of `shade(prim, q, d)` — triangle `prim` seen at point
/// `q` (the fragment's centroid) along the unit direction `d` — and the scene's environment where
/// the background shows (its radiance along the direction through the background fragment's
/// centroid: exact for a constant environment). Regions of [`super::region_side`]² pixels run in
/// parallel; `pixels_done(n)` is called after each with its pixel count (for a progress bar).
pub fn primary_image(
    scene: &Scene,
    camera: &Camera,
    shade: impl Fn(u32, Vec3, Vec3) -> Vec3 + Sync,
    pixels_done: impl Fn(u64) + Sync,
) -> (Image, PrimaryStats) {
    let start = Instant::now();
    let parts: Vec<Part> = regions(camera.width, camera.height)
        .into_par_iter()
        .map(|region| {
            let mut pixels = vec![Vec3::ZERO; region.len()];
            let mut coverage = vec![0.0f32; region.len()];
            let mut seen = vec![false; scene.triangles.len()];
            let mut fragments = 0u64;
            let mut eye = EyeStats::default();
            region_fragments(scene, camera, region, region, false, &mut eye, &mut seen, |x, y, cov, f| {
                let i = region.index(x, y);
                coverage[i] += cov;
                match f {
                    Fragment::Surface { prim, q, d } => {
                        fragments += 1;
                        pixels[i] += cov * shade(prim, q, d);
                    }
                    Fragment::Background { d } => pixels[i] += cov * scene.environment.radiance(d),
                    Fragment::Lit { .. } => {}
                }
            });
            let error = coverage.iter().fold(0.0f64, |m, &c| m.max(f64::from((1.0 - c).abs())));
            pixels_done(region.len() as u64);
            Part { region, pixels, eye, fragments, error, seen }
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
        let (image, stats) = primary_image(&scene, &camera, |_, _, _| Vec3::ONE, |_| {});
        assert!(stats.coverage_error < 1e-3, "coverage error {}", stats.coverage_error);
        for (i, p) in image.pixels.iter().enumerate() {
            assert!((p.x - 1.0).abs() < 1e-3, "pixel {i}: {p}");
        }
        assert!(stats.visible_triangles >= 10 && stats.hit_beams >= stats.visible_triangles);
        assert!(stats.fragments >= 48 * 32);
        // A shade of the primitive's index shows which triangle covers each pixel's centre.
        let (ids, _) = primary_image(&scene, &camera, |prim, _, _| Vec3::splat(prim as f32), |_| {});
        let frame = camera.frame();
        let pure = ids.pixels.iter().enumerate().filter(|&(i, p)| {
            let hit = scene.wide.closest_hit(camera.pixel_ray(&frame, i), f32::INFINITY).unwrap();
            (p.x - hit.prim as f32).abs() < 1e-3
        });
        assert!(pure.count() > 48 * 32 * 3 / 4, "most pixels lie inside one triangle, the one rays see");
    }
}
