//! Exact primary visibility a region at a time (001 §3): the eye beam through a region of pixels
//! is split into visible pieces ([`super::primary_beam`]), rasterized with exact box-filtered
//! coverage into fragments (a piece within a pixel, [`super::coverage`]), and, for point lights,
//! connected to the light by hard-shadow beams (001 §4.2) whose lit parts come as fragments too.

use super::coverage::{PixelGrid, pixel_parts};
use super::hard_shadow::{LitParts, lit_parts};
use super::primary_beam::{TrianglePlane, visible_surface_within};
use super::shadow_beam::BeamStats;
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, Section};
use beam_render::image::Image;
use beam_scene::region::PixelRect;
use beam_scene::scene::{Camera, Light, Material, Scene};

/// Tiles of the shading (and of primary rays), in pixels.
pub const TILE: u32 = 16;

/// Largest side of the image regions one eye beam covers, in pixels (a multiple of [`TILE`]). One
/// beam for a large region walks the top of the BVH once and splits a visible triangle only where
/// it crosses a region's edge; a smaller frame gets smaller regions ([`region_side`]).
pub const REGION: u32 = 256;

/// Offset of the 2 × 2 Gauss points from a pixel's centre, in pixels: ½ / √3.
const GAUSS: f32 = 0.288_675_13;

/// Regions a frame is cut into at least, where the smallest side allows: enough to share among
/// threads (a 128² frame in one region traced on one core).
const MIN_REGIONS: u32 = 16;

/// The side of the eye-beam regions of a `width × height` frame: the largest power of two from 32
/// to [`REGION`] that cuts it into at least 16 (`MIN_REGIONS`). It depends on the frame alone, so that
/// every tile of a render farm's frame cuts the visible surface at the same lines.
#[must_use]
pub fn region_side(width: u32, height: u32) -> u32 {
    let mut side = REGION;
    while side > 2 * TILE && width.div_ceil(side) * height.div_ceil(side) < MIN_REGIONS {
        side /= 2;
    }
    side
}

/// A rectangle of pixels `[x0, x1) × [y0, y1)` of the frame: an eye beam's region, a tile.
pub(crate) type Region = PixelRect;

/// Copy `region`'s row-major `pixels` into their place in `image`, the whole frame.
pub(crate) fn paste(region: Region, pixels: &[Vec3], image: &mut Image) {
    paste_within(region, pixels, image, PixelRect::full(image.width, image.height));
}

/// Copy the pixels of `region`'s row-major `pixels` that lie in `crop` (a rectangle of the frame)
/// into their place in `image`, which holds `crop`.
pub(crate) fn paste_within(region: Region, pixels: &[Vec3], image: &mut Image, crop: Region) {
    let (x0, x1) = (region.x0.max(crop.x0), region.x1.min(crop.x1));
    if x0 >= x1 {
        return;
    }
    let w = (x1 - x0) as usize;
    for y in region.y0.max(crop.y0)..region.y1.min(crop.y1) {
        let to = crop.index(x0, y);
        let from = region.index(x0, y);
        image.pixels[to..to + w].copy_from_slice(&pixels[from..from + w]);
    }
}

/// The regions of a `width × height` image, row by row.
pub(crate) fn regions(width: u32, height: u32) -> Vec<Region> {
    regions_in(width, height, PixelRect::full(width, height))
}

/// The regions of a `width × height` image that hold pixels of `within`, row by row: the image's
/// own grid of [`region_side`]² squares (anchored at its corner, whatever `within` is), so that an eye
/// beam splits the visible surface at the same lines as in the whole image.
pub(crate) fn regions_in(width: u32, height: u32, within: PixelRect) -> Vec<Region> {
    let within = within.intersect(PixelRect::full(width, height));
    let mut out = Vec::new();
    if within.is_empty() {
        return out;
    }
    let side = region_side(width, height);
    for y0 in (within.y0 / side * side..within.y1).step_by(side as usize) {
        for x0 in (within.x0 / side * side..within.x1).step_by(side as usize) {
            out.push(Region { x0, y0, x1: (x0 + side).min(width), y1: (y0 + side).min(height) });
        }
    }
    out
}

/// The image plane of `camera` as a beam frame: `u` along the camera's right, `v` down the image, so
/// that pixel `(x, y)` spans `[(2x/W − 1)·w, (2(x+1)/W − 1)·w] × [(2y/H − 1)·h, …]`. `None` for a
/// camera without a view ([`Camera::check_view`]).
pub(crate) fn image_frame(camera: &Camera) -> Option<(BeamFrame, f32, f32)> {
    camera.check_view().ok()?;
    let f = camera.frame();
    let frame = BeamFrame::new(camera.position, camera.position + f.forward, f.forward, f.right)?;
    Some((frame, f.half_width, f.half_height))
}

/// What a fragment of the eye beams (a visible piece within a pixel) sees.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Fragment<'a> {
    /// Nothing: the background (the environment), seen along the unit direction `d` through the
    /// fragment's centroid.
    Background { d: Vec3 },
    /// Triangle `prim` at point `q` (at the fragment's centroid), seen along `d`.
    Surface { prim: u32, q: Vec3, d: Vec3 },
    /// A fragment of a diffuse or glossy triangle that gathers no light but its point lights'
    /// ([`EyeBeam::lit_only`]): its coverage only, its light all in its [`Fragment::Lit`] parts.
    Covered,
    /// The part of a surface fragment lit by point light `light` (001 §4.2); its light is added to
    /// the surface fragment's, which then leaves that light out. The light varies fast near the
    /// light, so it is integrated over the fragment: `points` are the surface points of a quadrature
    /// on the image plane with weights summing to the coverage, exact for cubics on a whole pixel
    /// (2 × 2 Gauss points) and for quadratics on a part of one (edge midpoints of a fan around the
    /// centroid).
    Lit { light: usize, prim: u32, points: &'a [(f32, Vec3)] },
}

/// Work done by the beams of a region.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct EyeStats {
    pub(crate) primary: BeamStats,
    pub(crate) shadow: BeamStats,
    pub(crate) shadow_beams: u64,
    /// Pieces the eye beams ended with.
    pub(crate) pieces: u64,
    /// Seconds spent tracing the eye beams (summed over threads).
    pub(crate) trace_seconds: f64,
    /// Eye beams stopped at their budget (their regions went to rays).
    pub(crate) over_budget: u64,
}

/// One region's eye beam, as [`region_fragments`] is asked to trace it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EyeBeam<'a> {
    /// The pixels the beam covers.
    pub(crate) region: Region,
    /// The pixels (within `region`) whose fragments are wanted.
    pub(crate) window: Region,
    /// Whether each visible piece is connected to the point lights by hard-shadow beams.
    pub(crate) point_shadows: bool,
    /// With `point_shadows`: whether diffuse and glossy surfaces gather nothing else (no area
    /// light, sky or caustics), so that their surface fragments are [`Fragment::Covered`].
    pub(crate) lit_only: bool,
    /// Thread-seconds the trace may take ([`super::eye_budget::eye_trace_seconds`]).
    pub(crate) budget: f64,
    /// The triangles the caller's grid of rays through `region` saw, nearest first, which split
    /// the beam first (`None`: the beam casts its own grid).
    pub(crate) seeds: Option<&'a [u32]>,
}

impl EyeBeam<'_> {
    /// The exact beam through `region`, every fragment wanted, no point lights.
    pub(crate) fn exact(region: Region) -> Self {
        Self { region, window: region, point_shadows: false, lit_only: false, budget: f64::INFINITY, seeds: None }
    }
}

/// Every fragment of the exact visible surface seen through the pixels of `beam.region` (one eye
/// beam) that lies in the pixels of `beam.window`: calls `fragment(x, y, coverage, seen)` with the
/// fraction of pixel `(x, y)` a piece covers. With `beam.point_shadows`, each visible piece of a
/// diffuse or glossy triangle is also connected to every point light by a beam, and its lit parts
/// come as [`Fragment::Lit`]. Marks the triangles seen in `seen_prims`. A pixel's fragments do not
/// depend on the window: the pieces are the eye beam's through all of the region, and only the
/// pieces that reach no pixel of the window are skipped. False, with no fragment, when the trace
/// passes `beam.budget`. Cut-outs are opaque to eye beams and their hard shadows: regions that may
/// see one are the caller's to leave to rays ([`super::cut_outs`]).
pub(crate) fn region_fragments(
    scene: &Scene,
    camera: &Camera,
    beam: EyeBeam<'_>,
    stats: &mut EyeStats,
    seen_prims: &mut [bool],
    mut fragment: impl FnMut(u32, u32, f32, Fragment),
) -> bool {
    let EyeBeam { region, window, point_shadows, lit_only, budget, seeds } = beam;
    // A camera without a view sees nothing: the loaders and the CLI refuse one with its reason.
    let Some((frame, hw, hh)) = image_frame(camera) else { return true };
    let grid = PixelGrid::new(hw, hh, camera.width, camera.height);
    let corner = |x: u32, y: u32| grid.to_image(Vec2::new(x as f32, y as f32));
    let (lo, hi) = (corner(region.x0, region.y0), corner(region.x1, region.y1));
    let start = std::time::Instant::now();
    let pieces =
        visible_surface_within(&scene.bvh, &scene.triangles, &frame, (lo, hi), seeds, budget, &mut stats.primary);
    stats.trace_seconds += start.elapsed().as_secs_f64();
    let Some(pieces) = pieces else {
        stats.over_budget += 1;
        return false;
    };
    stats.pieces += pieces.len() as u64;
    let w = window.intersect(region);
    let window = (w.x0, w.y0, w.x1, w.y1);
    // Pieces at least a pixel away from the window have no fragment in it (their lit parts, cut
    // from them, neither): skipped, shadow beams and all.
    let (wlo, whi) = (Vec2::new(w.x0 as f32 - 1.0, w.y0 as f32 - 1.0), Vec2::new(w.x1 as f32 + 1.0, w.y1 as f32 + 1.0));
    let mut points = Vec::new();
    for piece in &pieces {
        let corners = piece.section.vertices().iter().map(|&c| grid.to_pixels(c));
        let (lo, hi) = corners.fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)));
        if !(lo.x < whi.x && lo.y < whi.y && hi.x > wlo.x && hi.y > wlo.y) {
            continue;
        }
        let Some(prim) = piece.prim else {
            pixel_parts(grid, &piece.section, window, |x, y, cov, part| {
                let d = (frame.point(grid.to_image(part.centroid())) - frame.apex).normalize_or_zero();
                fragment(x, y, cov, Fragment::Background { d });
            });
            continue;
        };
        seen_prims[prim as usize] = true;
        let plane = TrianglePlane::new(&frame, grid, &scene.triangles[prim as usize]);
        let lit = point_shadows && matches!(scene.material(prim), Material::Diffuse { .. } | Material::Glossy { .. });
        // Per point light, what it lights of the piece: a light that lights all of it is integrated
        // over the piece's own fragments, as they are found; the others over their lit parts.
        let (mut whole, mut cut) = (Vec::new(), Vec::new());
        for (light, l) in scene.lights.iter().enumerate().filter(|_| lit) {
            let Light::Point { position, .. } = *l else { continue };
            stats.shadow_beams += 1;
            match lit_parts(&scene.bvh, &scene.triangles, &frame, piece, position, &mut stats.shadow) {
                LitParts::Whole => whole.push(light),
                LitParts::Cut(parts) => cut.extend(parts.into_iter().map(|p| (light, p))),
            }
        }
        pixel_parts(grid, &piece.section, window, |x, y, cov, part| {
            if lit && lit_only {
                fragment(x, y, cov, Fragment::Covered);
            } else if let Some(q) = plane.point(part.centroid()) {
                fragment(x, y, cov, Fragment::Surface { prim, q, d: (q - frame.apex).normalize() });
            }
            if !whole.is_empty() {
                quadrature(&plane, (x, y), cov, part, &mut points);
                for &light in &whole {
                    fragment(x, y, cov, Fragment::Lit { light, prim, points: &points });
                }
            }
        });
        for (light, lit) in cut {
            pixel_parts(grid, &lit.section, window, |x, y, cov, part| {
                quadrature(&plane, (x, y), cov, part, &mut points);
                fragment(x, y, cov, Fragment::Lit { light, prim, points: &points });
            });
        }
    }
    true
}

/// The points of a fragment of `plane` in pixel `(x, y)`, the part `part` of coverage `cov`, with
/// the weights of a quadrature over it that sum to `cov`, into `points` ([`Fragment::Lit`]).
fn quadrature(plane: &TrianglePlane, (x, y): (u32, u32), cov: f32, part: &Section, points: &mut Vec<(f32, Vec3)>) {
    points.clear();
    let mut add = |w: f32, m: Vec2| points.extend(plane.point(m).map(|q| (w, q)));
    let v = part.vertices();
    if v.len() == 4 && cov >= 1.0 - 1e-6 {
        // The whole pixel: the 2 × 2 Gauss rule, exact for cubics.
        let c = Vec2::new(x as f32, y as f32) + 0.5;
        for (dx, dy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            add(cov / 4.0, c + GAUSS * Vec2::new(dx, dy));
        }
    } else {
        let c = part.centroid();
        for i in 0..v.len() {
            let (a, b) = (v[i], v[(i + 1) % v.len()]);
            // Pixel units: the areas are fractions of the pixel already.
            let w = (a - c).perp_dot(b - c).abs() / 6.0;
            for m in [0.5 * (c + a), 0.5 * (a + b), 0.5 * (b + c)] {
                add(w, m);
            }
        }
    }
}

/// Per pixel, the coverage of all visible pieces and of the pieces that see a triangle (exact
/// primary visibility by eye beams; both are 1 wherever geometry surrounds the camera).
#[must_use]
pub fn primary_coverage(scene: &Scene, width: u32, height: u32) -> Vec<(f32, f32)> {
    let camera = scene.camera.with_size(width, height);
    let mut out = vec![(0.0f32, 0.0f32); (width * height) as usize];
    let mut seen = vec![false; scene.triangles.len()];
    for region in regions(width, height) {
        let mut stats = EyeStats::default();
        let f = |x: u32, y: u32, cov: f32, seen: Fragment| {
            let o = &mut out[(y * width + x) as usize];
            o.0 += cov;
            if let Fragment::Surface { .. } | Fragment::Covered = seen {
                o.1 += cov;
            }
        };
        region_fragments(scene, &camera, EyeBeam::exact(region), &mut stats, &mut seen, f);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_math::Triangle;
    use beam_render::tolerance::shading_eps;

    /// A wall 559 units across (the Cornell box's back wall from Embree's test data) seen from
    /// about 2,600 away: every surface fragment lies on it within 1% of the shading tolerance, so
    /// that a shade point offset by that tolerance stays in front of it. Read from the pieces'
    /// f32 inverse depth instead, points lay up to 0.1 off (the tolerance itself), half of them
    /// behind the wall, and their shadow rays hit it: a grid of black dots.
    #[test]
    fn fragments_lie_on_their_triangle() {
        let z = 559.2;
        let v =
            [Vec3::new(549.6, 0.0, z), Vec3::new(0.0, 0.0, z), Vec3::new(0.0, 548.8, z), Vec3::new(556.0, 548.8, z)];
        let triangles = vec![(Triangle::new(v[0], v[1], v[2]), 0), (Triangle::new(v[0], v[2], v[3]), 0)];
        let camera = Camera {
            position: Vec3::new(1500.0, 1400.0, 2400.0),
            target: Vec3::new(278.0, 274.0, z),
            up: Vec3::Y,
            fov_y: 30.0,
            width: 96,
            height: 96,
        };
        let light = Light::Point { position: Vec3::new(278.0, 274.0, 1000.0), intensity: Vec3::ONE };
        let materials = vec![Material::Diffuse { albedo: Vec3::ONE }];
        let scene = Scene::new("wall".into(), triangles, materials, vec![light], camera);
        let tolerance = 0.01 * shading_eps(&scene);
        let region = Region { x0: 0, y0: 0, x1: 96, y1: 96 };
        let (mut stats, mut seen, mut worst, mut count) = (EyeStats::default(), vec![false; 2], 0.0f32, 0);
        let beam = EyeBeam { point_shadows: true, ..EyeBeam::exact(region) };
        region_fragments(&scene, &camera, beam, &mut stats, &mut seen, |_, _, _, f| {
            let points = match f {
                Fragment::Surface { q, .. } => vec![q],
                Fragment::Lit { points, .. } => points.iter().map(|&(_, q)| q).collect(),
                Fragment::Background { .. } | Fragment::Covered => Vec::new(),
            };
            for q in points {
                worst = worst.max((q.z - z).abs());
                count += 1;
            }
        });
        assert!(count > 1000, "{count} points");
        assert!(worst <= tolerance, "a point {worst} off the wall (tolerance {tolerance})");
    }
}
