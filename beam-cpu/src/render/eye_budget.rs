//! Whether an eye beam pays for a region of the image: its cost follows the visible triangles
//! (pieces are split at their edges, 001 §3), a ray's the pixels. A grid of rays through the region
//! finds how large the triangles it sees are on screen, and so about how many the region shows;
//! where sub-pixel triangles would make the pieces explode past a share of what the ray method
//! spends on the region, its pixels are sampled by primary rays instead (the same budget rule as
//! the shadow beams'), and the render says how many.

use beam_math::glam::Vec2;
use beam_scene::region::PixelRect;
use beam_scene::scene::{Camera, Scene};

/// Rays per side of the grid through a region.
const GRID: u32 = 16;

/// Thread-seconds per visible triangle of an eye beam, per pixel of its rasterization, and per ray
/// (this machine, `beam bench primary`: Sponza 512² 0.41 s for 16,274 visible triangles, the
/// Cornell box 128² 5 ms, rays 0.18 µs).
const PER_TRIANGLE: f64 = 20e-6;
const PER_PIXEL: f64 = 0.3e-6;
const PER_RAY: f64 = 0.18e-6;

/// The share of the ray method's time on a region (a primary ray and `spp` shadow rays a pixel)
/// the eye beam may take.
const SHARE: f64 = 0.5;

/// Whether the eye beam through `region` of `camera`'s image costs at most [`SHARE`] of the ray
/// method's time there at `spp` shadow rays per pixel, by the triangles a grid of rays sees and
/// their size on screen.
#[must_use]
pub(crate) fn eye_beam_pays(scene: &Scene, camera: &Camera, region: PixelRect, spp: u32) -> bool {
    let frame = camera.frame();
    let pixels = f64::from(region.width()) * f64::from(region.height());
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
    for j in 0..GRID {
        for i in 0..GRID {
            let x = region.x0 as f32 + (i as f32 + 0.5) / GRID as f32 * region.width() as f32;
            let y = region.y0 as f32 + (j as f32 + 0.5) / GRID as f32 * region.height() as f32;
            let Some(hit) = scene.wide.closest_hit(camera.ray(&frame, x, y), f32::INFINITY) else { continue };
            let t = &scene.triangles[hit.prim as usize];
            // The triangles of this cell's size that cover it (at least one).
            let area = match (to_pixels(t.v[0]), to_pixels(t.v[1]), to_pixels(t.v[2])) {
                (Some(a), Some(b), Some(c)) => f64::from(0.5 * (b - a).perp_dot(c - a).abs()),
                _ => cell,
            };
            visible += (cell / area.max(1e-3)).max(1.0);
        }
    }
    let eye = PER_TRIANGLE * visible + PER_PIXEL * pixels;
    let rays = PER_RAY * pixels * f64::from(1 + spp);
    eye <= SHARE * rays
}
