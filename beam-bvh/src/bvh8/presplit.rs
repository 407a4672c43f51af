//! Triangle pre-splitting for the high-quality 8-wide build (early split clipping; the budget
//! and priorities follow Karras and Aila, "Fast Parallel Construction of High-Quality Bounding
//! Volume Hierarchies", 2013, §4). A large triangle's box covers much empty space, and no split
//! of whole triangles can take it back; splitting the triangle into pieces, each with the box of
//! its part, lets the binned builder separate them. Triangles get extra references in proportion
//! to `(2^-level · (A(box) − 2·A(triangle)))^(1/3)`, with `level` that of the coarsest plane of the
//! scene's power-of-two grid crossing the box (the box surface they waste, weighted by how high in
//! the tree the split would matter: Karras and Aila's priority), up to a budget; each is cut at
//! that coarsest plane until it has its share of pieces, so that pieces of neighbouring triangles
//! line up with the splits a top-down builder makes.
//!
//! A piece's box is the box of the clipped polygon, widened by 2^-20 of the coordinates'
//! magnitude (so rounding in the clipping never leaves part of the triangle outside every piece)
//! and kept inside the triangle's own box. Queries test the whole triangle in every leaf it
//! reaches, so hits are unchanged.

use super::polygon::{MAX_VERTICES, Polygon};
use crate::binning::PrimRef;
use beam_math::heuristics::surface_area;
use beam_math::{Aabb, Triangle};
use std::vec::Vec;

/// `refs` with large triangles split into up to `budget · refs.len()` extra references.
pub(super) fn presplit(refs: Vec<PrimRef>, triangles: &[Triangle], budget: f32, scene: Aabb) -> Vec<PrimRef> {
    let extra = (budget.max(0.0) * refs.len() as f32) as usize;
    let priority = |r: &PrimRef| {
        let b = r.bounds().aabb();
        let Some((level, ..)) = grid_plane(b, &scene) else { return 0.0 };
        let waste = (surface_area(b) - 2.0 * triangles[r.index() as usize].area()).max(0.0);
        (waste / (1u32 << level) as f32).cbrt()
    };
    let total: f64 = refs.iter().map(|r| f64::from(priority(r))).sum();
    if extra == 0 || !(total > 0.0) {
        return refs;
    }
    let scale = extra as f64 / total;
    let mut out = Vec::with_capacity(refs.len() + extra);
    for r in refs {
        let pieces = 1 + (f64::from(priority(&r)) * scale) as usize;
        if pieces == 1 {
            out.push(r);
            continue;
        }
        let t = &triangles[r.index() as usize];
        let whole = r.bounds().aabb();
        let eps = whole.min.abs().max(whole.max.abs()).max_element() * (1.0 / (1 << 20) as f32);
        let piece = |p: &Polygon| {
            let b = p.bounds();
            let b = Aabb::new((b.min - eps).max(whole.min), (b.max + eps).min(whole.max));
            PrimRef::with_box(b, r.index())
        };
        split(&Polygon::triangle(t), pieces, &scene, &mut |p| out.push(piece(p)));
    }
    out
}

/// Cut `p` into `pieces` pieces, handing each to `emit`.
fn split(p: &Polygon, pieces: usize, scene: &Aabb, emit: &mut impl FnMut(&Polygon)) {
    let Some((_, axis, plane)) = (pieces > 1 && p.len < MAX_VERTICES).then(|| grid_plane(p.bounds(), scene)).flatten()
    else {
        emit(p);
        return;
    };
    let (left, right) = p.cut(axis, plane);
    if left.len < 3 || right.len < 3 {
        emit(p);
        return;
    }
    let (al, ar) = (surface_area(left.bounds()), surface_area(right.bounds()));
    let share = (pieces as f32 * al / (al + ar)).round() as usize;
    let l = share.clamp(1, pieces - 1);
    split(&left, l, scene, emit);
    split(&right, pieces - l, scene, emit);
}

/// The coarsest plane of `scene`'s power-of-two grid strictly inside `b` (the axis whose crossing
/// plane is coarsest; among equals the longest), as `(level, axis, coordinate)`.
fn grid_plane(b: Aabb, scene: &Aabb) -> Option<(u32, usize, f32)> {
    let mut best: Option<(u32, f32, usize, f32)> = None;
    for a in 0..3 {
        let (lo, size) = (scene.min[a], scene.max[a] - scene.min[a]);
        if !(size > 0.0) || !(b.max[a] > b.min[a]) {
            continue;
        }
        for level in 1..24u32 {
            let cell = size / (1u32 << level) as f32;
            let plane = lo + ((b.min[a] - lo) / cell).floor() * cell + cell;
            if plane > b.min[a] && plane < b.max[a] {
                let extent = b.max[a] - b.min[a];
                if best.is_none_or(|(l, e, ..)| level < l || (level == l && extent > e)) {
                    best = Some((level, extent, a, plane));
                }
                break;
            }
        }
    }
    best.map(|(level, _, a, plane)| (level, a, plane))
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_math::glam::Vec3;

    /// Every point of a split triangle lies in some piece's box, and no piece leaves the
    /// triangle's box.
    #[test]
    fn pieces_cover_the_triangle() {
        let t = Triangle::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, 1.0, 3.0), Vec3::new(2.0, 9.0, -4.0));
        let whole = Aabb::from_points(&t.v);
        let mut boxes = Vec::new();
        let scene = Aabb::new(Vec3::splat(-20.0), Vec3::splat(20.0));
        split(&Polygon::triangle(&t), 7, &scene, &mut |p| boxes.push(p.bounds()));
        assert_eq!(boxes.len(), 7);
        let area: f32 = boxes.iter().map(|b| surface_area(*b)).sum();
        assert!(area < surface_area(whole), "pieces should waste less than the whole box");
        for i in 0..=40 {
            for j in 0..=(40 - i) {
                let p = t.point(Vec3::new(1.0 - (i + j) as f32 / 40.0, i as f32 / 40.0, j as f32 / 40.0));
                let eps = 1e-5;
                let inside =
                    |b: &Aabb| (p - b.min).cmpge(Vec3::splat(-eps)).all() && (b.max - p).cmpge(Vec3::splat(-eps)).all();
                assert!(boxes.iter().any(inside), "{p} outside every piece");
            }
        }
    }
}
