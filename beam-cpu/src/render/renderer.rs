//! The renderer: the image a part at a time (primary rays or eye beams, `trace`), each part's
//! points shaded (`shading`: direct light by exact shadow beams, 001 §5, or by stratified shadow
//! rays, with the same shading, so that the two images differ only by the rays' noise), the parts
//! assembled and the counters summed (`stats`).

use super::eye_regions::{Region, TILE, paste_within, regions_in};
use super::image::Image;
use beam_scene::queries::AnyHit;
use beam_scene::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Instant;
use trace::{EyeTraced, TileRadiance, Trace, Traced};

mod emitters;
mod light_beam;
mod shade_points;
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
    let ctx = Context::new(scene, options, occluded, None);
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
        // Eye beams a region at a time, in parallel; then the regions' tiles are shaded in
        // parallel (a small image is one region, and its shading is most of the work).
        let regions = regions_in(camera.width, camera.height, work);
        let mut traced: Vec<EyeTraced> =
            regions.into_par_iter().map(|region| trace.eye_region(region, region.intersect(work))).collect();
        let jobs: Vec<(usize, usize, usize)> = traced
            .iter()
            .enumerate()
            .flat_map(|(r, e)| {
                e.tiles.iter().scan(0, move |start, &len| {
                    *start += len;
                    Some((r, *start - len, *start))
                })
            })
            .collect();
        // A row of tiles is done once every tile of it with fragments is.
        let tile_row = |e: &EyeTraced, start: usize| e.surfaces[start].y / TILE;
        let rows = camera.height.div_ceil(TILE) as usize;
        let left: Vec<AtomicU32> = (0..rows).map(|_| AtomicU32::new(0)).collect();
        for &(r, start, _) in &jobs {
            left[tile_row(&traced[r], start) as usize].fetch_add(1, Ordering::Relaxed);
        }
        let done_rows = |row: u32| {
            let r = Region { x0: 0, y0: row * TILE, x1: camera.width, y1: ((row + 1) * TILE).min(camera.height) };
            (0..rows_of(r)).for_each(|_| row_done());
        };
        for row in (0..rows as u32).filter(|&row| left[row as usize].load(Ordering::Relaxed) == 0) {
            done_rows(row);
        }
        let shaded: Vec<(usize, TileRadiance, Counters)> = jobs
            .par_iter()
            .map_init(Thread::default, |t, &(r, start, end)| {
                let e = &traced[r];
                let before = t.c;
                let out = trace.shade_eye_tile(e.traced.region, &e.surfaces[start..end], e.lights, t);
                let row = tile_row(e, start);
                if left[row as usize].fetch_sub(1, Ordering::Relaxed) == 1 {
                    done_rows(row);
                }
                (r, out, t.c.since(&before))
            })
            .collect();
        for (r, out, counters) in shaded {
            let part = &mut traced[r].traced;
            for (i, l) in out {
                part.pixels[i] += l;
            }
            part.counters += counters;
        }
        traced.into_iter().map(|e| e.traced).collect()
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
        merged_lights: scene.stats.merged_lights,
        notices: scene.notices.clone(),
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
        shade_points: total.shade_points,
        ray_pixels: total.ray_pixels,
        coverage_error: total.coverage_error,
        triangle_tests: total.beams.triangle_tests,
        pieces: total.beams.pieces,
        silhouette_beams: total.beams.silhouette_beams,
        silhouette_edges: total.beams.silhouette_edges,
        silhouette_fallbacks: total.beams.silhouette_fallbacks,
        sampled_beams: total.sampled_beams,
        culled_lights: total.culled_lights,
        environment: scene.environment.describe(),
        environment_lights: ctx.lights.len() - scene.lights.len(),
        environment_rays: total.environment_rays,
        exact_pixel_share: 1.0 - total.inexact_pixels as f64 / pixels,
        max_error_bound: total.max_error_bound,
        shafts: total.shafts,
        shaft_bvh_steps: total.shaft_bvh_steps,
        primary_seconds: total.primary_seconds,
        shadow_seconds: total.shadow_seconds,
        shading_seconds: total.shading_seconds,
    };
    (image, stats)
}
