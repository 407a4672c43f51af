//! Exact primary visibility a tile at a time (001 §3): the eye beam of a tile of pixels is split
//! into visible pieces ([`super::primary_beam`]), rasterized with exact box-filtered coverage into
//! fragments (a piece within a pixel), and, for point lights, connected to the light by hard-shadow
//! beams (001 §4.2) whose lit parts come as fragments too.

use super::hard_shadow::lit_pieces;
use super::primary_beam::{Piece, point_on_piece, visible_surface};
use super::shadow_beam::BeamStats;
use crate::scene::{Camera, Light, Material, Scene};
use beam_math::collide::ConvexPolygon;
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, Section};

/// Tiles of the eye beams, in pixels.
pub const TILE: u32 = 16;

/// The image plane of `camera` as a beam frame: `u` along the camera's right, `v` down the image, so
/// that pixel `(x, y)` spans `[(2x/W − 1)·w, (2(x+1)/W − 1)·w] × [(2y/H − 1)·h, …]`.
pub(crate) fn image_frame(camera: &Camera) -> (BeamFrame, f32, f32) {
    let f = camera.frame();
    let frame = BeamFrame::new(camera.position, camera.position + f.forward, f.forward, f.right)
        .expect("a camera frame is valid");
    (frame, f.half_width, f.half_height)
}

/// What a fragment of the eye beams (a visible piece within a pixel) sees.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Fragment<'a> {
    /// Nothing: the background.
    Background,
    /// Triangle `prim` at point `q` (at the fragment's centroid), seen along `d`.
    Surface { prim: u32, q: Vec3, d: Vec3 },
    /// The part of a surface fragment lit by point light `light` (001 §4.2); its light is added to
    /// the surface fragment's, which then leaves that light out. The light varies fast near the
    /// light, so it is integrated over the fragment: `points` are the surface points of a quadrature
    /// exact for quadratics on the image plane (edge midpoints of a fan around the centroid), with
    /// weights summing to the coverage.
    Lit { light: usize, prim: u32, points: &'a [(f32, Vec3)] },
}

/// Work done by the beams of a tile.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TileStats {
    pub(crate) primary: BeamStats,
    pub(crate) shadow: BeamStats,
    pub(crate) shadow_beams: u64,
}

/// Every fragment of the exact visible surface seen through pixels of tile `(tx, ty)`: calls
/// `fragment(x, y, coverage, seen)` with the fraction of pixel `(x, y)` a piece covers. With
/// `point_shadows`, each visible piece of a diffuse or glossy triangle is also connected to every
/// point light by a beam, and its lit parts come as [`Fragment::Lit`]. Marks the triangles seen in
/// `seen_prims`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn tile_fragments(
    scene: &Scene,
    camera: &Camera,
    tx: u32,
    ty: u32,
    point_shadows: bool,
    stats: &mut TileStats,
    seen_prims: &mut [bool],
    mut fragment: impl FnMut(u32, u32, f32, Fragment),
) {
    let (frame, hw, hh) = image_frame(camera);
    let (w, h) = (camera.width as f32, camera.height as f32);
    let px = |x: u32| (2.0 * x as f32 / w - 1.0) * hw;
    let py = |y: u32| (2.0 * y as f32 / h - 1.0) * hh;
    let (x0, y0) = (tx * TILE, ty * TILE);
    let (x1, y1) = ((x0 + TILE).min(camera.width), (y0 + TILE).min(camera.height));
    let pieces = visible_surface(
        &scene.bvh,
        &scene.triangles,
        &frame,
        Vec2::new(px(x0), py(y0)),
        Vec2::new(px(x1), py(y1)),
        &mut stats.primary,
    );
    let pixel_area = (2.0 * hw / w) * (2.0 * hh / h);
    let mut points = Vec::new();
    // Calls `f(x, y, coverage, piece ∩ pixel)` for every pixel of the tile `piece` covers.
    let rasterize = |piece: &Piece, f: &mut dyn FnMut(u32, u32, f32, &Section)| {
        let (lo, hi) = piece.section.bounds();
        let col = |c: f32, half: f32, n: f32| ((c / half + 1.0) * 0.5 * n).floor();
        let (cx0, cx1) = ((col(lo.x, hw, w).max(x0 as f32)) as u32, (col(hi.x, hw, w) as u32).min(x1 - 1));
        let (cy0, cy1) = ((col(lo.y, hh, h).max(y0 as f32)) as u32, (col(hi.y, hh, h) as u32).min(y1 - 1));
        for y in cy0..=cy1 {
            for x in cx0..=cx1 {
                let square = [
                    Vec2::new(px(x), py(y)),
                    Vec2::new(px(x + 1), py(y)),
                    Vec2::new(px(x + 1), py(y + 1)),
                    Vec2::new(px(x), py(y + 1)),
                ];
                let Ok(square) = ConvexPolygon::<4>::from_slice(&square) else { continue };
                let Ok(part) = piece.section.clip_by(&square) else { continue };
                let area = part.area();
                if area > 0.0 {
                    f(x, y, area / pixel_area, &part);
                }
            }
        }
    };
    for piece in &pieces {
        let Some(prim) = piece.prim else {
            rasterize(piece, &mut |x, y, cov, _| fragment(x, y, cov, Fragment::Background));
            continue;
        };
        seen_prims[prim as usize] = true;
        rasterize(piece, &mut |x, y, cov, part| {
            if let Some(q) = point_on_piece(&frame, piece, part.centroid()) {
                fragment(x, y, cov, Fragment::Surface { prim, q, d: (q - frame.apex).normalize() });
            }
        });
        if !point_shadows || !matches!(scene.material(prim), Material::Diffuse { .. } | Material::Glossy { .. }) {
            continue;
        }
        for (light, l) in scene.lights.iter().enumerate() {
            let Light::Point { position, .. } = *l else { continue };
            stats.shadow_beams += 1;
            for lit in lit_pieces(&scene.bvh, &scene.triangles, &frame, piece, position, &mut stats.shadow) {
                rasterize(&lit, &mut |x, y, cov, part| {
                    let (v, c) = (part.vertices(), part.centroid());
                    points.clear();
                    for i in 0..v.len() {
                        let (a, b) = (v[i], v[(i + 1) % v.len()]);
                        let w = (a - c).perp_dot(b - c).abs() / 6.0 / pixel_area;
                        for m in [0.5 * (c + a), 0.5 * (a + b), 0.5 * (b + c)] {
                            points.extend(point_on_piece(&frame, &lit, m).map(|q| (w, q)));
                        }
                    }
                    fragment(x, y, cov, Fragment::Lit { light, prim, points: &points });
                });
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
    for ty in 0..height.div_ceil(TILE) {
        for tx in 0..width.div_ceil(TILE) {
            let mut stats = TileStats::default();
            tile_fragments(scene, &camera, tx, ty, false, &mut stats, &mut seen, |x, y, cov, seen| {
                let o = &mut out[(y * width + x) as usize];
                o.0 += cov;
                if let Fragment::Surface { .. } = seen {
                    o.1 += cov;
                }
            });
        }
    }
    out
}
