//! Shafts (coherent shadow beams): the convex hull of a box of shade points and a light polygon
//! bounds every segment from one of those points to the light, so a triangle outside it occludes
//! none of them. Each cluster of a tile's shade points gathers its candidate occluders once through
//! the 8-wide BVH (eight boxes, then four triangles at a time), and each of its shade points then
//! splits its shadow beam by those candidates only, largest first, instead of walking the BVH from
//! its root (001 §3.3: "only the first beam needs to walk all the way to the leaves").

use beam_bvh::{Bvh8, Control, FlatBvh, Node8, NodeVisitor, Tri4};
use beam_math::collide::aabb_outside_planes;
use beam_math::glam::{BVec4A, Vec3, Vec4};
use beam_math::{Aabb, Triangle};
use core::ops::ControlFlow;

/// Most planes of a shaft: the light's plane and one through each edge of a light of at most 8
/// corners.
const MAX_PLANES: usize = 9;

/// A conservative bound of the segments from a box of points to a convex light polygon: half-spaces
/// `n·x ≤ d` (the light's plane and, through each light edge, the plane that supports the box) and
/// the bounding box of both.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shaft {
    planes: [(Vec3, f32); MAX_PLANES],
    len: usize,
    bounds: Aabb,
    /// The box's corners and the light's: the shaft is their convex hull.
    ends: [Vec3; 8 + MAX_PLANES - 1],
    ends_len: usize,
    /// How far from its planes a point still counts as on them.
    tol: f32,
}

impl Shaft {
    /// The shaft from the points in `points` to `light` (corners in order; `light_normal` points to
    /// the side the points are on).
    pub(crate) fn new(points: &Aabb, light: &[Vec3], light_normal: Vec3) -> Self {
        let bounds = light.iter().fold(*points, |b, &c| b.grow(c));
        let tol = 1e-5 * bounds.extent().length().max(f32::MIN_POSITIVE);
        let grow = Vec3::splat(tol);
        let mut ends = [Vec3::ZERO; 8 + MAX_PLANES - 1];
        let ends_len = 8 + light.len().min(MAX_PLANES - 1);
        ends[..8].copy_from_slice(&points.corners());
        ends[8..ends_len].copy_from_slice(&light[..ends_len - 8]);
        let mut out = Self {
            ends,
            ends_len,
            planes: [(Vec3::ZERO, 0.0); MAX_PLANES],
            len: 0,
            bounds: Aabb::new(bounds.min - grow, bounds.max + grow),
            tol,
        };
        // Nothing behind the light's plane: −N·x ≤ −N·l₀ + tol.
        out.push(-light_normal, -light_normal.dot(light[0]) + tol);
        let centroid = light.iter().copied().sum::<Vec3>() / light.len() as f32;
        let corners = points.corners();
        for i in 0..light.len().min(MAX_PLANES - 1) {
            let (a, b) = (light[i], light[(i + 1) % light.len()]);
            // The face of the hull through this edge passes through a corner of the box: the plane
            // through the edge and the corner that keeps every other corner inside.
            for &x in &corners {
                let Some(mut n) = (b - a).cross(x - a).try_normalize() else { continue };
                if n.dot(centroid - a) > 0.0 {
                    n = -n;
                }
                let d = n.dot(a);
                if corners.iter().all(|&y| n.dot(y) <= d + tol) {
                    out.push(n, d + tol);
                    break;
                }
            }
        }
        out
    }

    fn push(&mut self, n: Vec3, d: f32) {
        self.planes[self.len] = (n, d);
        self.len += 1;
    }

    /// False only when `b` lies outside the shaft.
    pub(crate) fn meets_box(&self, b: &Aabb) -> bool {
        let s = &self.bounds;
        b.min.cmple(s.max).all() && b.max.cmpge(s.min).all() && !aabb_outside_planes(b, &self.planes[..self.len])
    }

    /// [`Shaft::meets_box`] of the eight children of `n` at once, as bit `i` for `n.child[i]`
    /// (an unused slot's empty box meets nothing).
    fn meets_children(&self, n: &Node8) -> u32 {
        let s = &self.bounds;
        let mut mask = 0;
        for half in 0..2 {
            let lane = |k: usize| Vec4::from_slice(&n.bounds[k][4 * half..4 * half + 4]);
            let (lo, hi) = ([lane(0), lane(2), lane(4)], [lane(1), lane(3), lane(5)]);
            let mut meets = BVec4A::splat(true);
            for a in 0..3 {
                meets &= lo[a].cmple(Vec4::splat(s.max[a])) & hi[a].cmpge(Vec4::splat(s.min[a]));
            }
            for &(p, d) in &self.planes[..self.len] {
                // The corner least along the plane's normal: outside when even it lies beyond.
                let corner = |a: usize| if p[a] > 0.0 { lo[a] } else { hi[a] };
                meets &= (corner(0) * p.x + corner(1) * p.y + corner(2) * p.z).cmple(Vec4::splat(d));
            }
            mask |= meets.bitmask() << (4 * half);
        }
        mask
    }

    /// [`Shaft::meets_triangle`] of the four lanes of `b` at once, as bit `i` for lane `i`: the
    /// same operations in the same order, so the same answer (an unused lane's NaN corners meet
    /// nothing).
    fn meets_block(&self, b: &Tri4) -> u32 {
        let s = &self.bounds;
        let v = |k: usize, a: usize| Vec4::from_array(b.v[k][a]);
        let mut meets = BVec4A::splat(true);
        for a in 0..3 {
            let (x, y, z) = (v(0, a), v(1, a), v(2, a));
            meets &= x.max(y).max(z).cmpge(Vec4::splat(s.min[a])) & x.min(y).min(z).cmple(Vec4::splat(s.max[a]));
        }
        for &(p, d) in &self.planes[..self.len] {
            let below = |k: usize| (v(k, 0) * p.x + v(k, 1) * p.y + v(k, 2) * p.z).cmple(Vec4::splat(d));
            meets &= below(0) | below(1) | below(2);
        }
        meets.bitmask()
    }

    /// [`Shaft::crosses`] of the four lanes of `b` at once, as bit `i` for lane `i`, and their
    /// areas ([`Triangle::area`]): the same operations in the same order, so the same answers.
    fn crosses_block(&self, b: &Tri4) -> (u32, Vec4) {
        type V3 = [Vec4; 3];
        let corner = |k: usize| -> V3 { core::array::from_fn(|a| Vec4::from_array(b.v[k][a])) };
        let (v0, v1, v2) = (corner(0), corner(1), corner(2));
        let sub = |x: V3, y: V3| -> V3 { [x[0] - y[0], x[1] - y[1], x[2] - y[2]] };
        let dot = |x: V3, y: V3| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        let splat = |p: Vec3| -> V3 { [Vec4::splat(p.x), Vec4::splat(p.y), Vec4::splat(p.z)] };
        // Behind the light: every corner on the light's plane or beyond.
        let (light_n, light_0) = (splat(self.planes[0].0), splat(self.ends[8]));
        let beyond = |v: V3| dot(light_n, sub(v, light_0)).cmpge(Vec4::splat(-self.tol));
        let behind = beyond(v0) & beyond(v1) & beyond(v2);
        // Beside its plane: every end strictly on one side.
        let (e1, e2) = (sub(v1, v0), sub(v2, v0));
        let n = [e1[1] * e2[2] - e2[1] * e1[2], e1[2] * e2[0] - e2[2] * e1[0], e1[0] * e2[1] - e2[0] * e1[1]];
        let d = dot(n, v0);
        let length = |x: V3| Vec4::from_array(dot(x, x).to_array().map(f32::sqrt));
        let n_length = length(n);
        let tol = Vec4::splat(1e-5) * n_length * length(e1).max(length(e2));
        let (mut above, mut below) = (BVec4A::splat(true), BVec4A::splat(true));
        for &x in &self.ends[..self.ends_len] {
            let h = dot(n, splat(x)) - d;
            above &= h.cmpgt(tol);
            below &= h.cmplt(-tol);
        }
        (!(behind | above | below).bitmask() & 0xf, Vec4::splat(0.5) * n_length)
    }

    /// False only when `t` lies outside the shaft.
    pub(crate) fn meets_triangle(&self, t: &Triangle) -> bool {
        let s = &self.bounds;
        let [a, b, c] = t.v;
        a.max(b).max(c).cmpge(s.min).all()
            && a.min(b).min(c).cmple(s.max).all()
            && self.planes[..self.len].iter().all(|&(n, d)| n.dot(a) <= d || n.dot(b) <= d || n.dot(c) <= d)
    }

    /// Whether `t` may hide part of the light from a point of the box: it meets the shaft, does
    /// not lie behind the light and its plane does not leave the box and the light on one side.
    pub(crate) fn may_hide(&self, t: &Triangle) -> bool {
        self.meets_triangle(t) && self.crosses(t)
    }

    /// [`Shaft::may_hide`] of a triangle that meets the shaft.
    fn crosses(&self, t: &Triangle) -> bool {
        !self.behind_light(t) && !self.beside_plane_of(t)
    }

    /// True when `t` lies on the light's plane or beyond it (within the shaft's tolerance): a
    /// segment from the box ends at the light before it would reach `t`. The light's own
    /// neighbours on a curved emitter (a lamp's other triangles) touch it along an edge and lie
    /// behind it: without this each of its beams clipped them.
    fn behind_light(&self, t: &Triangle) -> bool {
        // The first plane is the light's, `−N·x ≤ −N·l₀ + tol`; the light's corners follow the box's.
        let n = self.planes[0].0;
        t.v.iter().all(|&v| n.dot(v - self.ends[8]) >= -self.tol)
    }

    /// True when the box and the light lie strictly on one side of `t`'s plane: no segment from
    /// the box to the light crosses it, so `t` hides nothing (a wall or a floor beside the points;
    /// 001 §3.4 marks back faces once per query for the same reason).
    pub(crate) fn beside_plane_of(&self, t: &Triangle) -> bool {
        let n = t.scaled_normal();
        let d = n.dot(t.v[0]);
        // A margin relative to the triangle's size keeps the test conservative under rounding.
        let tol = 1e-5 * n.length() * (t.v[1] - t.v[0]).length().max((t.v[2] - t.v[0]).length());
        let ends = &self.ends[..self.ends_len];
        ends.iter().all(|&x| n.dot(x) - d > tol) || ends.iter().all(|&x| n.dot(x) - d < -tol)
    }
}

/// Finds whether any triangle meets a shaft, stopping at the first.
struct Meets<'a> {
    shaft: &'a Shaft,
    triangles: &'a [Triangle],
    found: bool,
    steps: u64,
}

impl NodeVisitor for Meets<'_> {
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        self.steps += 1;
        self.shaft.meets_box(bounds).then_some(0.0)
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        self.found = prims.iter().any(|&p| self.shaft.may_hide(&self.triangles[p as usize]));
        if self.found { Control::Stop } else { Control::Continue }
    }
}

/// Whether some triangle of the BVH may hide part of the light from a point of the shaft's box
/// (the test [`gather`] keeps a candidate by), and the BVH nodes tested: `false` means every
/// point of the box sees the whole light.
pub(crate) fn meets_any(bvh: &FlatBvh, triangles: &[Triangle], shaft: &Shaft) -> (bool, u64) {
    let mut m = Meets { shaft, triangles, found: false, steps: 0 };
    bvh.traverse(&mut m);
    (m.found, m.steps)
}

/// Most candidates a shaft gathers: past this many (a wide shaft through a dense room), each point's
/// own BVH walk is cheaper than testing the list, and [`gather`] gives up.
pub(crate) const MAX_CANDIDATES: usize = 2048;

/// Fill `out` with every triangle of the BVH that may hide part of the light from a point of
/// `shaft`'s box ([`Shaft::may_hide`]), larger triangles first: they are the likelier to hide the
/// whole light and end a shadow beam before the others split it (3× fewer splits on Sponza than in
/// BVH order; weighting by the projected size from the points did worse). The 8-wide BVH is
/// tested eight boxes and four triangles at a time. Returns the BVH nodes visited; `out` holds
/// more than [`MAX_CANDIDATES`] when it gave up.
pub(crate) fn gather(bvh: &Bvh8, triangles: &[Triangle], shaft: &Shaft, out: &mut Vec<(u32, u32)>) -> u64 {
    out.clear();
    let mut steps = 0;
    let enter = |n: &Node8| {
        steps += 1;
        shaft.meets_children(n)
    };
    bvh.visit_leaves(enter, |first, count| {
        for (block, b) in bvh.blocks[first..first + count].iter().enumerate() {
            let mut lanes = shaft.meets_block(b);
            if lanes == 0 {
                continue;
            }
            let (crosses, area) = shaft.crosses_block(b);
            debug_assert!((0..4).all(|l| {
                let prim = bvh.prims[4 * (first + block) + l];
                prim == u32::MAX || {
                    let t = &triangles[prim as usize];
                    ((lanes & crosses) >> l & 1 == 1) == shaft.may_hide(t) && t.area() == area[l]
                }
            }));
            lanes &= crosses;
            while lanes != 0 {
                let lane = lanes.trailing_zeros() as usize;
                lanes &= lanes - 1;
                out.push((area[lane].to_bits(), bvh.prims[4 * (first + block) + lane]));
            }
        }
        if out.len() > MAX_CANDIDATES { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    });
    // (area key, triangle): areas are non-negative, so their bits order them. A triangle in two
    // leaves (a tree with split references) comes once.
    out.sort_unstable_by(|a, b| b.cmp(a));
    out.dedup();
    steps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shaft_keeps_what_lies_between_and_drops_what_does_not() {
        let light = [
            Vec3::new(-0.5, 2.0, -0.5),
            Vec3::new(0.5, 2.0, -0.5),
            Vec3::new(0.5, 2.0, 0.5),
            Vec3::new(-0.5, 2.0, 0.5),
        ];
        let points = Aabb::new(Vec3::new(-0.1, 0.0, -0.1), Vec3::new(0.1, 0.0, 0.1));
        let shaft = Shaft::new(&points, &light, -Vec3::Y);
        let tri = |c: Vec3, r: f32| {
            Triangle::new(c + Vec3::new(-r, 0.0, -r), c + Vec3::new(r, 0.0, -r), c + Vec3::new(0.0, 0.0, r))
        };
        assert!(shaft.meets_triangle(&tri(Vec3::new(0.0, 1.0, 0.0), 0.05)));
        // Beside the shaft halfway up (its half-width there is about 0.3), above the light, below the points.
        assert!(!shaft.meets_triangle(&tri(Vec3::new(0.6, 1.0, 0.0), 0.05)));
        assert!(!shaft.meets_triangle(&tri(Vec3::new(0.0, 2.5, 0.0), 0.05)));
        assert!(!shaft.meets_triangle(&tri(Vec3::new(0.0, -0.5, 0.0), 0.05)));
        // A floor under the points and a wall beside them: both in the box, beside it all.
        let floor =
            Triangle::new(Vec3::new(-5.0, -0.01, -5.0), Vec3::new(5.0, -0.01, -5.0), Vec3::new(0.0, -0.01, 5.0));
        let wall = Triangle::new(Vec3::new(0.2, -1.0, -5.0), Vec3::new(0.2, -1.0, 5.0), Vec3::new(0.2, 3.0, 0.0));
        assert!(shaft.beside_plane_of(&floor) && !shaft.beside_plane_of(&wall));
        let beside = Triangle::new(Vec3::new(0.6, -1.0, -5.0), Vec3::new(0.6, -1.0, 5.0), Vec3::new(0.6, 3.0, 0.0));
        assert!(shaft.beside_plane_of(&beside));
        // Seeded segments from the box to the light: a small triangle around any of their points meets it.
        let mut s = 7u32;
        let mut r = move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..2000 {
            let p = points.min + (points.max - points.min) * Vec3::new(r(), r(), r());
            let l = light[0] + (light[1] - light[0]) * r() + (light[3] - light[0]) * r();
            let x = p + (l - p) * r();
            assert!(shaft.meets_triangle(&tri(x, 1e-4)), "{x}");
            assert!(shaft.meets_box(&Aabb::new(x - 1e-4, x + 1e-4)));
        }
    }

    /// Through the 8-wide BVH, eight boxes and four triangles at a time, [`gather`] finds exactly
    /// the triangles that [`Shaft::may_hide`] keeps one by one, largest first, and gives up past
    /// [`MAX_CANDIDATES`]: seeded soups of triangles of many sizes around seeded shafts.
    #[test]
    fn gather_keeps_what_the_triangle_test_keeps() {
        let mut s = 11u32;
        let mut r = move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut out = Vec::new();
        for round in 0..20 {
            let n = if round == 0 { 4000 } else { 1500 };
            let tris: Vec<Triangle> = (0..n)
                .map(|_| {
                    let c = Vec3::new(4.0 * r() - 2.0, 3.0 * r() - 0.5, 4.0 * r() - 2.0);
                    let size = 0.5 * r() * r();
                    let mut corner = || c + size * Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5);
                    Triangle::new(corner(), corner(), corner())
                })
                .collect();
            let bvh = Bvh8::build(&tris, &beam_bvh::BuildOptions::sah());
            // The first shaft spans the soup, from under it to a light over it all.
            let (y, w) = if round == 0 { (3.0, 2.5) } else { (2.0 + r(), 0.1 + r()) };
            let light = [Vec3::new(-w, y, -w), Vec3::new(w, y, -w), Vec3::new(w, y, w), Vec3::new(-w, y, w)];
            let points = if round == 0 {
                Aabb::new(Vec3::new(-2.0, -0.7, -2.0), Vec3::new(2.0, -0.6, 2.0))
            } else {
                let lo = Vec3::new(2.0 * r() - 1.0, 0.0, 2.0 * r() - 1.0);
                Aabb::new(lo, lo + Vec3::new(0.3 * r(), 0.1 * r(), 0.3 * r()))
            };
            let shaft = Shaft::new(&points, &light, -Vec3::Y);
            gather(&bvh, &tris, &shaft, &mut out);
            let mut expected: Vec<(u32, u32)> = (0..n as u32)
                .filter(|&i| tris[i as usize].is_valid() && shaft.may_hide(&tris[i as usize]))
                .map(|i| (tris[i as usize].area().to_bits(), i))
                .collect();
            expected.sort_unstable_by(|a, b| b.cmp(a));
            if round == 0 {
                assert!(expected.len() > MAX_CANDIDATES && out.len() > MAX_CANDIDATES, "{}", expected.len());
                assert!(out.len() < expected.len(), "gave up before it gathered them all");
            } else {
                assert!(!expected.is_empty(), "round {round}: the shaft meets part of the soup");
                assert_eq!(out, expected, "round {round}");
            }
        }
    }
}
