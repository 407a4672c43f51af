//! The renderer: the image a part at a time (primary rays or eye beams, `trace`), each part's
//! points shaded (`shading`: direct light by exact shadow beams, 001 §5, or by stratified shadow
//! rays, with the same shading, so that the two images differ only by the rays' noise), the parts
//! assembled and the counters summed (`stats`).

use super::eye_regions::{Region, TILE, paste_within, regions_in};
use beam_render::image::Image;
use beam_render::queries::AnyHit;
use beam_scene::scene::Scene;
use rayon::prelude::*;
use std::time::Instant;
use trace::{Trace, Traced};

mod context;
mod emitters;
mod light_beam;
pub(crate) mod light_samples;
mod point_lit;
mod rounds;
mod shade_points;
mod shading;
mod sky;
mod stats;
mod tile_chains;
mod trace;
mod wavefront;

use context::{Context, pixel_seed};
use stats::Counters;
pub use stats::RenderStats;

pub use shading::{shade_point, stratified, trace_radiance};
pub use wavefront::{light_seen, pixel_fragments, render_queries};

use beam_render::options::{Method, RenderOptions};

/// Render `scene` (the pixels of `options.region` only, each as in the whole frame); `row_done` is
/// called after each image row (for a progress bar).
pub fn render(scene: &Scene, options: &RenderOptions, row_done: impl Fn() + Sync) -> (Image, RenderStats) {
    render_by(scene, options, None, row_done)
}

/// [`render`] with another shadow-ray tracer (for benchmarks against peers).
pub fn render_with(
    scene: &Scene,
    options: &RenderOptions,
    occluded: &AnyHit<'_>,
    row_done: impl Fn() + Sync,
) -> (Image, RenderStats) {
    render_by(scene, options, Some(occluded), row_done)
}

/// [`render`], shadow rays traced by `peer` or else by the scene's own BVH.
fn render_by(
    scene: &Scene,
    options: &RenderOptions,
    peer: Option<&AnyHit<'_>>,
    row_done: impl Fn() + Sync,
) -> (Image, RenderStats) {
    let start = Instant::now();
    let camera = scene.camera.with_size(options.width, options.height);
    let ctx = Context::new(scene, options, peer, None);
    let pixel_seed = |x: u32, y: u32| pixel_seed(options.seed, x, y);
    let eye_beams = options.method == Method::Beam && options.primary_beams;
    let n_prims = if eye_beams { scene.triangles.len() } else { 0 };
    let trace = Trace { ctx: &ctx, camera: &camera, seed: &pixel_seed, n_prims };
    // The pixels asked for, and those computed: whole shading tiles of the frame's grid, since a
    // tile's shade points share their candidate occluders (a pixel gets its whole-frame value only
    // with its tile's others); with beams, whole rows of tiles, since a tile starts from how the
    // one to its left ended.
    let crop = options.region();
    let mut work = crop.aligned_out(TILE, camera.width, camera.height);
    if options.method == Method::Beam && !work.is_empty() {
        (work.x0, work.x1) = (0, camera.width);
    }
    let rows_of = |part: Region| crop.y1.min(part.y1).saturating_sub(crop.y0.max(part.y0));
    // Eye beams a region of the frame's grid at a time (the pixels of `work` in it), primary rays a
    // band of TILE rows at a time, in parallel; each returns its pixels, counters and the triangles
    // it saw.
    let parts: Vec<Traced> = if crop.is_empty() {
        Vec::new()
    } else if eye_beams {
        // The regions of the frame's grid traced and their rows of tiles shaded, as jobs.
        let regions = regions_in(camera.width, camera.height, work);
        let bands: Vec<&[Region]> = regions.chunk_by(|a, b| a.y0 == b.y0).collect();
        tile_chains::trace_and_shade(&trace, &bands, work, &|rows| (0..rows_of(rows)).for_each(|_| row_done()))
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
    let stats = RenderStats::summed(
        scene,
        options,
        (image.width, image.height),
        &total,
        visible_triangles,
        ctx.lights.len() - scene.lights.len(),
        start.elapsed().as_secs_f64(),
    );
    (image, stats)
}
