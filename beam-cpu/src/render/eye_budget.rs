//! Whether an eye beam pays for a region of the image: its cost follows the visible triangles
//! (pieces are split at their edges, 001 §3), a ray's the pixels. A grid of rays through the region
//! finds how large the triangles it sees are on screen, and so about how many the region shows;
//! where sub-pixel triangles would make the pieces explode past a share of what the ray method
//! spends on the region, its pixels are sampled by primary rays instead (the same budget rule as
//! the shadow beams'), and the render says how many. The grid can miss a thin band of such
//! triangles, so the trace itself also stops once its work ([`eye_trace_seconds`]) passes the
//! budget, and the region goes to rays after all.

use super::shadow_beam::BeamStats;
use beam_math::glam::Vec2;
use beam_scene::region::PixelRect;
use beam_scene::scene::{Camera, Scene};

/// Rays per side of the grid through a region ([`grid_hits`]).
pub(crate) const GRID: u32 = 16;

/// Thread-seconds per visible triangle of an eye beam, per pixel of its rasterization, and per ray
/// (this machine, `beam bench primary`: Sponza 512² 0.41 s for 16,274 visible triangles, the
/// Cornell box 128² 5 ms, rays 0.18 µs).
const PER_TRIANGLE: f64 = 20e-6;
const PER_PIXEL: f64 = 0.3e-6;
const PER_RAY: f64 = 0.18e-6;

/// Thread-seconds per piece tested against a triangle, per triangle set up and per hit beam of an
/// eye beam's trace (this machine, one thread: a least-squares fit over the 1,056 regions of
/// `beam bench primary --sweep`, Sponza and the conference room, correlation 0.99).
const PER_CHECK: f64 = 3.7e-8;
const PER_TEST: f64 = 4.3e-7;
const PER_HIT: f64 = 2.0e-6;

/// The share of the ray method's time on a region (a primary ray and `spp` shadow rays a pixel)
/// the eye beam may take.
const SHARE: f64 = 0.5;

/// How many times the time of the rays that replace it (a few a pixel, shaded the same way) an
/// eye beam may take for its exact coverage. Where triangles are a few pixels large (Sponza, the
/// Šibenik cathedral, the conference room at 256²) an eye beam costs 1–9 µs a pixel against
/// 0.6–1.2 µs for 2 × 2 rays; at 512² 0.2–2 µs (224 regions of seven scenes at 256² and 512²).
/// With the renderer's rays (counted as 3 a pixel, `renderer/trace.rs`), 3 sends Sponza 256² 62%
/// to rays, 512² 25%, the conference room 31% at 256² and 6% at 512², the plant at 512² none.
const EXACTNESS: f64 = 3.0;

/// How many times its prediction an eye beam's trace may take: on the shared scenes and the
/// built-in ones at 512² the trace's work stays within 1.7× of it, but where a dense mesh lies
/// just behind the visible surface (the conference room's folded curtain, seen at a grazing
/// angle) every hidden triangle is tested and split against, which the grid of rays cannot see:
/// that region took 8.9× its prediction, 0.08 s of eye beam for 16,384 pixels. 2.5 sends the
/// same regions to rays as 4 did on the 15 shared and built-in scenes at 256² and 512² (the curtain,
/// two of Šibenik's at 256² and one of `foliage`'s), and wastes less on each before it does.
const SURPRISE: f64 = 2.5;

/// The thread-seconds an eye beam's trace has taken, predicted from its work: `stats` and `checks`
/// pieces tested against triangles. Deterministic, so that a budget on it cuts the same regions on
/// every run and machine.
#[must_use]
pub(crate) fn eye_trace_seconds(stats: &BeamStats, checks: u64) -> f64 {
    PER_CHECK * checks as f64 + PER_TEST * stats.triangle_tests as f64 + PER_HIT * stats.hit_beams as f64
}

/// The thread-seconds the trace of `region`'s eye beam may take, where the ray method traces
/// `rays` a pixel and `fallback` rays a pixel would replace the beam: `None` where it is predicted
/// to take more than [`eye_budget`] ([`eye_beam_seconds`] from the region's [`grid_hits`]), else
/// that budget but no more than [`SURPRISE`] times the prediction.
#[must_use]
pub(crate) fn trace_budget(
    scene: &Scene,
    camera: &Camera,
    (region, hits): (PixelRect, &[(f32, u32)]),
    (rays, fallback): (u32, u32),
) -> Option<f64> {
    let (budget, predicted) = (eye_budget(region, rays, fallback), eye_beam_seconds(scene, camera, region, hits));
    (predicted <= budget).then(|| budget.min(SURPRISE * predicted))
}

/// The thread-seconds the eye beam of `region` may take at most: [`SHARE`] of what the ray
/// method's `rays` a pixel take, and [`EXACTNESS`] times what the `fallback` rays a pixel that
/// would replace it take.
#[must_use]
fn eye_budget(region: PixelRect, rays: u32, fallback: u32) -> f64 {
    (SHARE * ray_seconds(region, rays)).min(EXACTNESS * ray_seconds(region, fallback))
}

/// The thread-seconds `rays` rays a pixel of `region` take.
#[must_use]
fn ray_seconds(region: PixelRect, rays: u32) -> f64 {
    PER_RAY * region.len() as f64 * f64::from(rays)
}

/// The hits `(t, prim)` of a `GRID × GRID` grid of camera rays through the cell centres of
/// `region` (`t` in units of the image plane's distance): what predicts the region's eye beam
/// ([`trace_budget`]) and, nearest first, what splits it first
/// ([`nearest_first`](super::primary_beam::nearest_first)).
#[must_use]
pub(crate) fn grid_hits(scene: &Scene, camera: &Camera, region: PixelRect) -> Vec<(f32, u32)> {
    let frame = camera.frame();
    let mut hits = Vec::with_capacity((GRID * GRID) as usize);
    for j in 0..GRID {
        for i in 0..GRID {
            let x = region.x0 as f32 + (i as f32 + 0.5) / GRID as f32 * region.width() as f32;
            let y = region.y0 as f32 + (j as f32 + 0.5) / GRID as f32 * region.height() as f32;
            if let Some(hit) = scene.wide.closest_hit(camera.ray(&frame, x, y), f32::INFINITY) {
                hits.push((hit.t, hit.prim));
            }
        }
    }
    hits
}

/// The predicted thread-seconds of the eye beam through `region` of `camera`'s image, by the
/// triangles its grid of rays sees (`hits`, [`grid_hits`]) and their size on screen.
#[must_use]
fn eye_beam_seconds(scene: &Scene, camera: &Camera, region: PixelRect, hits: &[(f32, u32)]) -> f64 {
    let frame = camera.frame();
    let pixels = region.len() as f64;
    let cell = pixels / f64::from(GRID * GRID);
    // On screen, in pixels: the point's image coordinates.
    let to_pixels = |v: beam_math::glam::Vec3| {
        let w = v - camera.position;
        let z = w.dot(frame.forward);
        (z > 0.0).then(|| {
            let s = Vec2::new(w.dot(frame.right) / (z * frame.half_width), w.dot(frame.up) / (z * frame.half_height));
            Vec2::new((s.x + 1.0) * 0.5 * camera.width as f32, (1.0 - s.y) * 0.5 * camera.height as f32)
        })
    };
    let mut visible = 0.0f64;
    for &(_, prim) in hits {
        let t = &scene.triangles[prim as usize];
        // The cell's share of the triangles it sees, `cell / area`: summed over the cells, an
        // estimate of the visible triangles (a triangle of area A is hit by about A / cell of
        // them). A triangle reaching behind the eye counts as the size of the region.
        let area = match (to_pixels(t.v[0]), to_pixels(t.v[1]), to_pixels(t.v[2])) {
            (Some(a), Some(b), Some(c)) => f64::from(0.5 * (b - a).perp_dot(c - a).abs()),
            _ => pixels,
        };
        visible += cell / area.max(1e-3);
    }
    PER_TRIANGLE * visible + PER_PIXEL * pixels
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::eye_regions::{EyeBeam, EyeStats, Fragment, region_fragments, regions};
    use crate::render::primary_beam::nearest_first;
    use beam_scene::scene::builtin;
    use std::collections::HashMap;

    /// The grid that predicts a region's eye beam also seeds it, in place of the beam's own: the
    /// seeds change only the order the beam is split in, so each pixel's coverage by each triangle
    /// is the same.
    #[test]
    fn the_prediction_grid_seeds_the_beam_without_changing_it() {
        let scene = builtin("foliage").unwrap();
        let camera = scene.camera.with_size(64, 64);
        let coverage = |region, seeds: Option<&[u32]>| {
            let mut out: HashMap<(u32, u32, u32), f32> = HashMap::new();
            let (mut stats, mut seen) = (EyeStats::default(), vec![false; scene.triangles.len()]);
            let beam = EyeBeam { seeds, ..EyeBeam::exact(region) };
            region_fragments(&scene, &camera, beam, &mut stats, &mut seen, |x, y, cov, f| {
                if let Fragment::Surface { prim, .. } = f {
                    *out.entry((x, y, prim)).or_default() += cov;
                }
            });
            out
        };
        let mut seeded = 0;
        for region in regions(camera.width, camera.height) {
            let seeds = nearest_first(grid_hits(&scene, &camera, region));
            let (own, shared) = (coverage(region, None), coverage(region, Some(&seeds)));
            for key in own.keys().chain(shared.keys()) {
                let (a, b) = (own.get(key).copied().unwrap_or(0.0), shared.get(key).copied().unwrap_or(0.0));
                assert!((a - b).abs() < 1e-4, "{region:?} {key:?}: {a} against {b}");
            }
            seeded += usize::from(!seeds.is_empty());
        }
        assert!(seeded > 1, "{seeded} regions seeded");
    }
}
