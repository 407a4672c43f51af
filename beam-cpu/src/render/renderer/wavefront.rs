//! The frame of the `beam` and `ray` methods as a host-driven wavefront, every visibility query
//! sent to a backend in batches ([`BeamQueries`]), so that a GPU can answer them: the camera rays
//! of a band of rows and the mirror and glass rays after them (`paths`), then the direct light at
//! every shade point they found (`plan`: shadow rays and shadow-beam queries; `gather`: the
//! backend's answers summed into irradiance), the band's pixels assembled.

use super::context::Context;
use super::stats::{Counters, RenderStats};
use crate::render::eye_regions::{Region, paste_within};
use batches::MAX_BATCH;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::image::Image;
use beam_render::options::{Method, RenderOptions};
use beam_render::queries::BeamQueries;
use beam_scene::scene::{Camera, Scene};
use plan::LightTable;
use std::f32::consts::PI;
use std::time::Instant;

mod batches;
mod exact_beam;
mod eye;
mod gather;
mod paths;
mod plan;

pub use exact_beam::light_seen;
pub use eye::pixel_fragments;

/// Render `scene` as [`render`](super::render) does with every shadow beam traced to the end
/// (`options.exact == true`), the visibility by
/// `backend`: its closest hits for the camera, mirror and glass rays, its any-hits for the shadow
/// rays of point lights, of the `ray` method's area-light samples and of the environment's
/// cosine-weighted samples, and its shadow beams (one [`LightQuery`](beam_render::queries::LightQuery)
/// a shade point and area light, a constant environment's six faces among the lights, as in
/// `render`) for the `beam` method. A beam the backend gives up on (`None`) is traced on the host
/// by [`light_seen`] and counted in [`RenderStats::overflow_beams`]. The image is computed a band
/// of rows at a time, each batch at most 2²⁰ rays, segments or beams; `row_done` is called after
/// each image row (of `options.region`, which crops as in `render`).
///
/// The same pixels as `render` with the same options (the same camera rays, jitter, seeds and box
/// filter, the `ray` method's samples from the same random streams), but:
/// - with `options.primary_beams`, every pixel's fragments come from eye beams (the backend's
///   where it gives them) except in the bands of rows (a batch's worth) that may see a cut-out:
///   those are seen through `options.primary_spp` primary rays (each counted in
///   `cut_out_regions`), where `render` sends the regions of its own grid that may see one;
/// - in a scene with cut-outs, the backend's hits on cut-out triangles are checked against their
///   alpha on the host and its rays sent on past them (a GPU tests no alpha), and an area light a
///   cut-out may hide from a shade point is sampled by `options.spp` shadow rays
///   (`cut_out_beams`), as in `render`, but decided per point rather than per cluster of points;
/// - every shadow beam is traced exactly, whatever `options.exact` and `options.spp`: no work
///   budget with its sampled remainder, no ray sampling below `render`'s fewest shadow rays for
///   beams, and none of `render`'s ways to the same exact answer faster (shading tiles, shafts and
///   their candidate occluders, silhouette edges and winding numbers; `options.occluders` is not
///   read), so the image equals `render`'s with `exact: true` to rounding;
/// - of the stats, the beams' work (`bvh_steps`, `intersections`, `hit_beams`, `triangle_tests`,
///   `pieces`, the silhouette and shaft counters), `culled_lights` and the eye beams' counters stay
///   0 (a backend does not report them); `shade_points` counts the points lit (0 in `render`'s
///   primary-ray frame); the `*_seconds` are the stages' wall time, not thread time.
pub fn render_queries(
    scene: &Scene,
    options: &RenderOptions,
    backend: &dyn BeamQueries,
    row_done: impl Fn() + Sync,
) -> Result<(Image, RenderStats), BackendError> {
    let start = Instant::now();
    let camera = scene.camera.with_size(options.width, options.height);
    // Every query goes to `backend`: the context's own shadow-ray tracer is never called.
    let ctx = Context::new(scene, options, None, None);
    let table = LightTable::new(&ctx);
    let crop = options.region();
    let k = ((options.primary_spp.max(1) as f32).sqrt() as u32).max(1);
    let mut image = Image::new(crop.width(), crop.height());
    let mut c = Counters::default();
    // Eye beams: every pixel's exact fragments first (the backend's, the rest the host's); but a
    // band that may see a cut-out (even behind something) is seen through primary rays, which test
    // the alpha (a region each). Bands are cut for the larger of the two sample counts.
    let eye_beams = options.method == Method::Beam && options.primary_beams;
    let per_pixel = if eye_beams { eye::EYE_SAMPLES.max(k * k) } else { k * k };
    let bands: Vec<(Region, bool)> = bands(crop, per_pixel)
        .map(|band| (band, eye_beams && !ctx.cut_outs.as_ref().is_some_and(|c| c.may_show(&camera, band))))
        .collect();
    for (band, _) in bands.iter().filter(|(_, by_beams)| eye_beams && !by_beams) {
        c.cut_out_regions += 1;
        c.ray_pixels += band.len() as u64;
    }
    let view = if bands.iter().any(|(_, by_beams)| *by_beams) {
        let eye_start = Instant::now();
        // The frame's pixels that eye beams see (row-major).
        let mut wanted = vec![false; camera.width as usize * camera.height as usize];
        for (b, _) in bands.iter().filter(|(_, by_beams)| *by_beams) {
            for y in b.y0..b.y1 {
                let row = (y * camera.width) as usize;
                wanted[row + b.x0 as usize..row + b.x1 as usize].fill(true);
            }
        }
        let (view, left) = eye::eye_view(scene, &camera, backend, &wanted)?;
        c.overflow_pixels += left;
        c.fragments +=
            view.iter().zip(&wanted).filter(|(_, w)| **w).map(|(p, _)| p.fragments.len() as u64).sum::<u64>();
        c.primary_seconds += eye_start.elapsed().as_secs_f64();
        Some(view)
    } else {
        None
    };
    for &(band, by_beams) in &bands {
        let primary = match &view {
            Some(v) if by_beams => paths::Primary::Fragments(v),
            _ => paths::Primary::Rays(k),
        };
        let pixels = shade_band(&ctx, &camera, backend, &table, band, primary, &mut c)?;
        paste_within(band, &pixels, &mut image, crop);
        if band.x1 == crop.x1 {
            (band.y0..band.y1).for_each(|_| row_done());
        }
    }
    let environment_lights = ctx.lights.len() - scene.lights.len();
    let seconds = start.elapsed().as_secs_f64();
    let stats = RenderStats::summed(scene, options, (image.width, image.height), &c, 0, environment_lights, seconds);
    Ok((image, stats))
}

/// The bands of `crop`, `per_pixel` camera rays a pixel: whole rows, as many as [`MAX_BATCH`]
/// rays allow (at least one); where one row has more, runs of one row's pixels.
fn bands(crop: Region, per_pixel: u32) -> impl Iterator<Item = Region> {
    let per_row = crop.width() as usize * per_pixel as usize;
    let (rows, cols) = if per_row <= MAX_BATCH {
        ((MAX_BATCH / per_row.max(1)) as u32, crop.width().max(1))
    } else {
        (1, (MAX_BATCH / per_pixel as usize).max(1) as u32)
    };
    (crop.y0..crop.y1).step_by(rows as usize).flat_map(move |y0| {
        let y1 = (y0 + rows).min(crop.y1);
        (crop.x0..crop.x1).step_by(cols as usize).map(move |x0| Region { x0, y0, x1: (x0 + cols).min(crop.x1), y1 })
    })
}

/// The pixels of `band` (seen through `primary`), row-major; the work counted into `c`.
fn shade_band(
    ctx: &Context<'_>,
    camera: &Camera,
    backend: &dyn BeamQueries,
    table: &LightTable,
    band: Region,
    primary: paths::Primary<'_>,
    c: &mut Counters,
) -> Result<Vec<Vec3>, BackendError> {
    let start = Instant::now();
    let per_pixel = primary.per_pixel();
    let paths::Band { mut pixels, points, rays } = paths::trace_band(ctx, camera, backend, band, primary)?;
    c.camera_rays += rays;
    c.primary_seconds += start.elapsed().as_secs_f64();
    // Slices of whole camera samples (their samples share a random stream) whose work fits a batch.
    let most = (MAX_BATCH / plan::most_work(ctx).max(1)).max(1);
    let mut inexact = vec![false; band.len()];
    let sky_bound = PI * ctx.scene.environment.max_radiance();
    let mut begin = 0;
    while begin < points.len() {
        let mut end = (begin + most).min(points.len());
        while end < points.len() && points[end].sample == points[end - 1].sample {
            end += 1;
        }
        let slice = &points[begin..end];
        let plan = plan::plan(ctx, table, slice, band, per_pixel);
        let lit = gather::gather(ctx, backend, table, slice, &plan, c)?;
        for (s, l) in slice.iter().zip(lit) {
            let pixel = (s.sample / per_pixel) as usize;
            pixels[pixel] += l.radiance;
            if l.sampled {
                // The sky's sampled irradiance lies in [0, π·max L], as its estimate does.
                inexact[pixel] = true;
                c.max_error_bound = c.max_error_bound.max(s.albedo.max_element() / PI * sky_bound);
            }
        }
        begin = end;
    }
    c.inexact_pixels += inexact.iter().filter(|&&i| i).count() as u64;
    Ok(pixels)
}
