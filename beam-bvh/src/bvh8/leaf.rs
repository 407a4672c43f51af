//! Leaves of the 8-wide layout: triangles in blocks of four, structure of arrays, intersected four
//! at a time by the watertight test of [`WatertightRay`] (Woop, Benthin, Wald 2013) evaluated lane
//! by lane with the same operations in the same order. A block therefore answers exactly what the
//! scalar test answers triangle by triangle, and shared edges stay closed; the rare lanes where an
//! edge function is exactly 0 take the scalar test's double-precision path, repeated here.
//!
//! [`WatertightRay`]: beam_math::collide::WatertightRay

use super::node::Node8;
use super::tree::Bvh8;
use super::tri4::Tri4;
use crate::traverse::Hit;
use beam_math::Ray;
use beam_math::glam::Vec4;

/// Per-ray constants of the watertight test in the form the lanes use: the dominant axis `kz`,
/// the shear as scalars, the permuted origin.
///
/// The scalar test swaps the other two axes when `d[kz] < 0` to keep the winding; the lanes do
/// not. Swapping x and y of every vertex negates the three edge functions exactly (each is a
/// difference of the same two products, taken the other way round), hence also `det` and the
/// scaled `t`, so `t = t_scaled / det` and the barycentrics come out the same: only the sign of
/// an exact zero can differ, which the tests treat alike.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearRay {
    /// The axes `kx`, `ky`, `kz`: vertex coordinates are read by these indices, so no branch
    /// depends on the ray's direction (shadow and bounce rays change it from ray to ray).
    k: [usize; 3],
    s: [f32; 3],
    o: [f32; 3],
}

impl ShearRay {
    /// The constants of `ray`, chosen exactly as [`WatertightRay::new`] chooses them (one
    /// four-lane division gives the three quotients, each rounded as the scalar one is).
    ///
    /// [`WatertightRay::new`]: beam_math::collide::WatertightRay::new
    #[inline(always)]
    pub(super) fn new(ray: Ray) -> Self {
        let (d, o) = (ray.direction.to_array(), ray.origin.to_array());
        let a = d.map(f32::abs);
        // The scalar test's choice (NaN included), as selects rather than branches.
        let k0 = usize::from(!(a[0] > a[1]));
        let kz = if a[k0] > a[2] { k0 } else { 2 };
        // kx = kz + 1, ky = kz + 2 (mod 3).
        let k = [(kz + 1) % 3, (kz + 2) % 3, kz];
        let s = Vec4::new(d[k[0]], d[k[1]], 1.0, 1.0) / Vec4::splat(d[k[2]]);
        Self { k, s: [s.x, s.y, s.z], o: k.map(|i| o[i]) }
    }
}

/// The lanes of a block that a ray hits within its interval.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BlockHits {
    /// Bit `i` set when lane `i` is hit.
    pub mask: u32,
    /// Ray parameters (in registers: read only the lanes of `mask`).
    pub t: Vec4,
    /// Barycentric weights of vertex 1.
    pub u: Vec4,
    /// Barycentric weights of vertex 2.
    pub v: Vec4,
}

impl BlockHits {
    /// No lane hit.
    pub(super) const NONE: Self = Self { mask: 0, t: Vec4::ZERO, u: Vec4::ZERO, v: Vec4::ZERO };

    /// The hit lane of smallest `t` (the last of equal ones, as a sequential scan keeps).
    #[inline(always)]
    pub(super) fn nearest(&self) -> usize {
        let mut best = self.mask.trailing_zeros() as usize;
        let mut m = self.mask & (self.mask - 1);
        while m != 0 {
            let i = m.trailing_zeros() as usize;
            if self.t[i] <= self.t[best] {
                best = i;
            }
            m &= m - 1;
        }
        best
    }
}

/// Intersect the four triangles of `b` with `r`, keeping hits with `t` in `[t_min, t_max]`.
#[inline(always)]
pub(crate) fn intersect4(b: &Tri4, r: &ShearRay, t_min: f32, t_max: f32) -> BlockHits {
    let Edges { abc, u, v, w, fallback, same } = edges(b, r);
    // Most blocks a ray meets have no lane that may be hit, and skip the rest of the test.
    if same | fallback == 0 {
        return BlockHits::NONE;
    }
    let det = u + v + w;
    let t_scaled = u * abc[2] + v * abc[5] + w * abc[8];
    let inv = Vec4::ONE / det;
    let t = t_scaled * inv;
    // NaN lanes (padding) fail the ordered comparisons.
    let ok = det.abs().cmplt(Vec4::INFINITY) & t.cmpge(Vec4::splat(t_min)) & t.cmple(Vec4::splat(t_max));
    let mut hits = BlockHits { mask: ok.bitmask() & same, t, u: v * inv, v: w * inv };
    if fallback != 0 {
        fallback_lanes(&abc.map(|x| x.to_array()), t_min, t_max, fallback, &mut hits);
    }
    hits
}

/// Whether `r` hits any triangle of `b` with `t` in `[0, t_max]`. Without the division of
/// [`intersect4`]: `t = t_scaled / det` is compared as `t_scaled` against `t_max · det`, which
/// can differ from the scalar test only for `t` within rounding of `t_max`.
#[inline(always)]
pub(crate) fn occludes4(b: &Tri4, r: &ShearRay, t_max: f32) -> bool {
    let Edges { abc, u, v, w, fallback, same } = edges(b, r);
    // Most blocks a ray meets have no lane that may be hit, and skip the rest of the test.
    if same | fallback == 0 {
        return false;
    }
    let det = u + v + w;
    let t_scaled = u * abc[2] + v * abc[5] + w * abc[8];
    // `t_scaled / det` in `[0, t_max]`, with both sides' signs flipped where `det < 0`.
    let flip = Vec4::select(det.cmplt(Vec4::ZERO), -Vec4::ONE, Vec4::ONE);
    let (ts, d) = (t_scaled * flip, det.abs());
    let ok = d.cmplt(Vec4::INFINITY) & ts.cmpge(Vec4::ZERO) & ts.cmple(Vec4::splat(t_max) * d);
    if ok.bitmask() & same != 0 {
        return true;
    }
    if fallback == 0 {
        return false;
    }
    let mut hits = BlockHits::NONE;
    fallback_lanes(&abc.map(|x| x.to_array()), 0.0, t_max, fallback, &mut hits);
    hits.mask != 0
}

/// Whether `hint` is a block of `bvh` one of whose triangles `sr` hits within `[0, t_max]`
/// ([`occludes4`]).
#[inline(always)]
pub(crate) fn hinted(bvh: &Bvh8, hint: u32, sr: &ShearRay, t_max: f32) -> bool {
    bvh.blocks.get(hint as usize).is_some_and(|b| occludes4(b, sr, t_max))
}

/// Test the blocks of leaf `r` of `bvh` (a [`Node8::LEAF`] reference) with `sr`, calling
/// `on_block` with each block's index before its test. With `ANY`: the first block hit within
/// `[0, t_best]`. Else the nearest hit there replaces `best` and becomes `t_best`; returns `None`.
#[inline(always)]
pub(crate) fn visit_leaf<const ANY: bool>(
    bvh: &Bvh8,
    r: u32,
    sr: &ShearRay,
    t_best: &mut f32,
    best: &mut Option<Hit>,
    mut on_block: impl FnMut(usize),
) -> Option<u32> {
    let (first, count) = Node8::leaf_blocks(r);
    for k in first..first + count {
        on_block(k);
        if ANY {
            if occludes4(&bvh.blocks[k], sr, *t_best) {
                return Some(k as u32);
            }
            continue;
        }
        let h = intersect4(&bvh.blocks[k], sr, 0.0, *t_best);
        if h.mask != 0 {
            let l = h.nearest();
            *t_best = h.t[l];
            *best = Some(Hit { prim: bvh.prims[4 * k + l], t: h.t[l], u: h.u[l], v: h.v[l] });
        }
    }
    None
}

/// The edge functions of four triangles for one ray: the lanes' transformed vertices and `u`,
/// `v`, `w` (weights of vertices 0, 1, 2).
struct Edges {
    abc: [Vec4; 9],
    u: Vec4,
    v: Vec4,
    w: Vec4,
    /// Lanes with an edge function exactly 0 (the scalar test's double-precision path).
    fallback: u32,
    /// Lanes whose edge functions are all nonzero and of one sign: hit if `t` is in range. With
    /// `fallback`, the lanes that may be hit (never padding, whose functions are NaN).
    same: u32,
}

#[inline(always)]
fn edges(b: &Tri4, r: &ShearRay) -> Edges {
    let [kx, ky, kz] = r.k;
    let (ox, oy, oz) = (Vec4::splat(r.o[0]), Vec4::splat(r.o[1]), Vec4::splat(r.o[2]));
    let (sx, sy, sz) = (Vec4::splat(r.s[0]), Vec4::splat(r.s[1]), Vec4::splat(r.s[2]));
    // Vertex `k` translated to the origin, permuted and sheared: `shear · (v − o)` of the scalar
    // test, whose matrix rows are `e_kx − Sx·e_kz`, `e_ky − Sy·e_kz`, `Sz·e_kz`.
    let vertex = |k: usize| {
        let dx = Vec4::from_array(b.v[k][kx]) - ox;
        let dy = Vec4::from_array(b.v[k][ky]) - oy;
        let dz = Vec4::from_array(b.v[k][kz]) - oz;
        (dx - sx * dz, dy - sy * dz, sz * dz)
    };
    let (ax, ay, az) = vertex(0);
    let (bx, by, bz) = vertex(1);
    let (cx, cy, cz) = vertex(2);
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    let zero = Vec4::ZERO;
    let fallback = (u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero)).bitmask();
    // One sign, none 0: the smallest above 0 or the largest below (NaN lanes are neither).
    // `det`, a sum of same-signed values, is then not 0.
    let (lo, hi) = (u.min(v.min(w)), u.max(v.max(w)));
    let same = (lo.cmpgt(zero) | hi.cmplt(zero)).bitmask();
    Edges { abc: [ax, ay, az, bx, by, bz, cx, cy, cz], u, v, w, fallback, same }
}

/// The lanes whose single-precision edge functions include an exact zero: the rest of the scalar
/// test after its switch to double precision, from the lanes' transformed vertices `abc`
/// (a.x, a.y, a.z, b.x, …).
#[cold]
#[inline(never)]
fn fallback_lanes(abc: &[[f32; 4]; 9], t_min: f32, t_max: f32, mut lanes: u32, hits: &mut BlockHits) {
    while lanes != 0 {
        let i = lanes.trailing_zeros() as usize;
        lanes &= lanes - 1;
        let [ax, ay, az, bx, by, bz, cx, cy, cz] = abc.map(|x| x[i]);
        let f = |px: f32, py: f32, qx: f32, qy: f32| (px as f64 * qy as f64 - py as f64 * qx as f64) as f32;
        let (u, v, w) = (f(cx, cy, bx, by), f(ax, ay, cx, cy), f(bx, by, ax, ay));
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            continue;
        }
        let det = u + v + w;
        if det == 0.0 || !det.is_finite() {
            continue;
        }
        let inv = 1.0 / det;
        let t = (u * az + v * bz + w * cz) * inv;
        if t >= t_min && t <= t_max {
            hits.mask |= 1 << i;
            (hits.t[i], hits.u[i], hits.v[i]) = (t, v * inv, w * inv);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traverse::tests::unit_rng;
    use beam_math::Triangle;
    use beam_math::collide::WatertightRay;
    use beam_math::glam::Vec3;

    fn rng(seed: u32) -> impl FnMut() -> f32 {
        let mut unit = unit_rng(seed);
        move || unit() * 2.0 - 1.0
    }

    /// Every lane answers bit for bit what the scalar test answers, on shared edges and vertices
    /// (where the double-precision fallback runs) as elsewhere.
    #[test]
    fn lanes_equal_the_scalar_test() {
        let mut r = rng(5);
        let mut p = || Vec3::new(r(), r(), r());
        let mut checked = 0;
        for i in 0..4000 {
            // A fan around a shared vertex, with rays aimed at its edges and vertices.
            let c = p();
            let tris: Vec<Triangle> = (0..4).map(|_| Triangle::new(c, c + p(), c + p())).collect();
            let mut block = Tri4::EMPTY;
            tris.iter().take(1 + i % 4).enumerate().for_each(|(l, t)| block.set(l, t));
            let origin = p() * 3.0;
            let target = match i % 3 {
                0 => c,
                1 => 0.5 * (tris[0].v[0] + tris[0].v[1]),
                _ => tris[1].v[2] + 0.1 * p(),
            };
            let ray = Ray::new(origin, target - origin);
            let (wt, sr) = (WatertightRay::new(ray), ShearRay::new(ray));
            let t_max = if i % 5 == 0 { 0.7 } else { f32::INFINITY };
            let hits = intersect4(&block, &sr, 0.0, t_max);
            for l in 0..4 {
                let want = (l <= i % 4).then(|| wt.intersect(&tris[l], 0.0, t_max)).flatten();
                let got = (hits.mask & (1 << l) != 0).then(|| (hits.t[l], hits.u[l], hits.v[l]));
                assert_eq!(got.map(|g| g.0.to_bits()), want.map(|w| w.t.to_bits()), "ray {i} lane {l}");
                assert_eq!(got.map(|g| (g.1, g.2)), want.map(|w| (w.u, w.v)), "ray {i} lane {l}");
                checked += usize::from(want.is_some());
            }
        }
        assert!(checked > 1000, "{checked} hits");
    }

    /// An axis-parallel ray through a vertex: edge functions exactly 0, the double-precision path.
    #[test]
    fn exact_zero_edges_take_the_double_precision_path() {
        let tri = Triangle::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0));
        let mut block = Tri4::EMPTY;
        block.set(2, &tri);
        for ray in [Ray::new(Vec3::ZERO, Vec3::Z), Ray::new(Vec3::new(0.5, 0.0, 3.0), -Vec3::Z)] {
            let want = WatertightRay::new(ray).intersect(&tri, 0.0, f32::INFINITY).expect("hit on the boundary");
            let h = intersect4(&block, &ShearRay::new(ray), 0.0, f32::INFINITY);
            assert_eq!(h.mask, 0b100);
            assert_eq!((h.t[2], h.u[2], h.v[2]), (want.t, want.u, want.v));
        }
    }
}
