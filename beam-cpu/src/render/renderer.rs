//! The renderer: the image a part at a time (primary rays or eye beams, `trace`), each part's
//! points shaded (`shading`: direct light by exact shadow beams, 001 §5, or by stratified shadow
//! rays, with the same shading, so that the two images differ only by the rays' noise), the parts
//! assembled and the counters summed (`stats`).

use super::eye_regions::{REGION, Region, TILE, paste_within, regions_in};
use super::image::Image;
use beam_scene::queries::AnyHit;
use beam_scene::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Instant;
use trace::{Trace, Traced};

mod shading;
mod stats;
mod trace;

use shading::{Context, Lights, Surface, Thread};
use stats::Counters;
pub use stats::RenderStats;

pub use beam_scene::tolerance::shading_eps;
pub use shading::{shade_point, stratified, trace_radiance};

pub use beam_scene::options::{Method, Occluders, RenderOptions, Shading};

/// Render `scene` (the pixels of `options.region` only, each as in the whole frame); `row_done` is
/// called after each image row (for a progress bar).
pub fn render(scene: &Scene, options: &RenderOptions, row_done: impl Fn() + Sync) -> (Image, RenderStats) {
    render_with(scene, options, &|ray, t_max| scene.wide.any_hit(ray, t_max), row_done)
}

/// [`render`] with another shadow-ray tracer (for benchmarks against peers).
pub fn render_with(
    scene: &Scene,
    options: &RenderOptions,
    occluded: &AnyHit<'_>,
    row_done: impl Fn() + Sync,
) -> (Image, RenderStats) {
    let start = Instant::now();
    let camera = scene.camera.with_size(options.width, options.height);
    let ctx = Context { scene, options: *options, eps: shading_eps(scene), occluded, caustics: None };
    let pixel_seed =
        |x: u32, y: u32| options.seed ^ (u64::from(y) << 32 | u64::from(x)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let eye_beams = options.method == Method::Beam && options.primary_beams;
    let n_prims = if eye_beams { scene.triangles.len() } else { 0 };
    let trace = Trace { ctx: &ctx, camera: &camera, seed: &pixel_seed, n_prims };
    // The pixels asked for, and those computed: whole shading tiles of the frame's grid, since a
    // tile's shade points share their candidate occluders (a pixel gets its whole-frame value only
    // with its tile's others).
    let crop = options.region();
    let work = crop.aligned_out(TILE, camera.width, camera.height);
    let rows_of = |part: Region| crop.y1.min(part.y1).saturating_sub(crop.y0.max(part.y0));
    // Eye beams a region of the frame's grid at a time (the pixels of `work` in it), primary rays a
    // band of TILE rows at a time, in parallel; each returns its pixels, counters and the triangles
    // it saw.
    let parts: Vec<Traced> = if crop.is_empty() {
        Vec::new()
    } else if eye_beams {
        let regions = regions_in(camera.width, camera.height, work);
        let across = regions.iter().filter(|r| r.y0 == regions[0].y0).count() as u32;
        let first_row = regions.first().map_or(0, |r| r.y0 / REGION);
        let done: Vec<AtomicU32> = (0..camera.height.div_ceil(REGION)).map(|_| AtomicU32::new(0)).collect();
        regions
            .into_par_iter()
            .map(|region| {
                let traced = trace.eye_region(region, region.intersect(work));
                // A row is done once every region across it is.
                let row = (region.y0 / REGION - first_row) as usize;
                if done[row].fetch_add(1, Ordering::Relaxed) + 1 == across {
                    (0..rows_of(region)).for_each(|_| row_done());
                }
                traced
            })
            .collect()
    } else {
        (work.y0 / TILE..work.y1.div_ceil(TILE))
            .into_par_iter()
            .map(|ty| {
                let y0 = ty * TILE;
                let traced =
                    trace.ray_band(Region { x0: work.x0, y0, x1: work.x1, y1: (y0 + TILE).min(camera.height) });
                (0..rows_of(traced.region)).for_each(|_| row_done());
                traced
            })
            .collect()
    };
    let mut image = Image::new(crop.width(), crop.height());
    let mut total = Counters::default();
    let mut visible = vec![false; n_prims];
    for part in parts {
        paste_within(part.region, &part.pixels, &mut image, crop);
        total += part.counters;
        for (v, s) in visible.iter_mut().zip(part.seen) {
            *v |= s;
        }
    }
    let visible_triangles = visible.iter().filter(|&&v| v).count() as u64;
    let pixels = (image.pixels.len() as f64).max(1.0);
    let stats = RenderStats {
        seconds: start.elapsed().as_secs_f64(),
        method: match options.method {
            Method::Beam => "beam",
            Method::Ray => "ray",
        }
        .into(),
        shading: match options.shading {
            Shading::Fraction => "fraction",
            Shading::Exact => "exact",
        }
        .into(),
        spp: if options.method == Method::Ray { options.spp } else { 0 },
        width: image.width,
        height: image.height,
        triangles: scene.stats.triangles,
        degenerate_triangles: scene.stats.degenerate,
        camera_rays: total.camera_rays,
        shadow_rays: total.shadow_rays,
        shadow_beams: total.shadow_beams,
        bvh_steps: total.beams.bvh_steps,
        intersections: total.beams.intersections,
        hit_beams: total.beams.hit_beams,
        hit_beams_per_pixel: total.beams.hit_beams as f64 / pixels,
        primary_bvh_steps: total.primary.bvh_steps,
        primary_intersections: total.primary.intersections,
        primary_hit_beams: total.primary.hit_beams,
        visible_triangles,
        hit_beams_per_visible_triangle: total.primary.hit_beams as f64 / visible_triangles.max(1) as f64,
        fragments: total.fragments,
        coverage_error: total.coverage_error,
        triangle_tests: total.beams.triangle_tests,
        pieces: total.beams.pieces,
        silhouette_beams: total.beams.silhouette_beams,
        silhouette_edges: total.beams.silhouette_edges,
        silhouette_fallbacks: total.beams.silhouette_fallbacks,
        shafts: total.shafts,
        shaft_bvh_steps: total.shaft_bvh_steps,
        primary_seconds: total.primary_seconds,
        shadow_seconds: total.shadow_seconds,
        shading_seconds: total.shading_seconds,
    };
    (image, stats)
}
