//! Candidate occluders four at a time: their corners in 4-lane vectors, so that one pass of
//! portable SIMD (glam's `Vec4`: SSE2 on x86-64, NEON on AArch64) projects four triangles onto a
//! shadow beam's light plane and rejects those that lie outside its depth range or beside its
//! remaining pieces before any of them is split (001 §3.4: each vertex projected once per query).

use beam_math::Triangle;
use beam_math::glam::{BVec4A, Vec2, Vec3, Vec4};
use beam_render::tolerance::DEPTH_EPS;

/// Four triangles, corner-major: `v[corner][axis]` holds that coordinate of the four.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Packet {
    v: [[Vec4; 3]; 3],
    /// Triangle indices of the lanes.
    pub(crate) prims: [u32; 4],
    /// Lanes in use (1 to 4); unused lanes repeat lane 0.
    pub(crate) len: u32,
}

/// What a shadow beam needs to project a packet: its apex, the light plane's axes and distance,
/// the apex's plane coordinates and the bounding rectangle of its remaining pieces.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Projector {
    pub(crate) apex: Vec3,
    pub(crate) u: Vec3,
    pub(crate) v: Vec3,
    pub(crate) normal: Vec3,
    pub(crate) distance: f32,
    pub(crate) apex_uv: Vec2,
    /// Depth range `[near, far]` along `normal`, in scene units.
    pub(crate) near: f32,
    pub(crate) far: f32,
    /// Depth before which a triangle is dropped (a triangle between it and `near` may touch the
    /// shade point, see `shadow_beam::CONTACT`).
    pub(crate) touch: f32,
    /// The light plane's origin, relative to the apex.
    pub(crate) origin: Vec3,
    /// The beam's fuzzy side tolerance on the light's plane.
    pub(crate) eps: f32,
}

impl Projector {
    /// The central projection of `x` (in the depth range) onto the light plane, in its coordinates.
    #[inline]
    pub(crate) fn project(&self, x: Vec3) -> Vec2 {
        let w = x - self.apex;
        self.apex_uv + Vec2::new(w.dot(self.u), w.dot(self.v)) * (self.distance / w.dot(self.normal))
    }
}

/// A lane that survived the packet test: its triangle index and, when the whole triangle lies in
/// the depth range, its projected corners.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Survivor {
    pub(crate) prim: u32,
    pub(crate) projected: Option<[Vec2; 3]>,
}

impl Packet {
    /// Pack up to four triangles (`prims` index `triangles`).
    pub(crate) fn new(triangles: &[Triangle], prims: &[u32]) -> Self {
        debug_assert!((1..=4).contains(&prims.len()));
        let lane = |i: usize| &triangles[prims[i.min(prims.len() - 1)] as usize];
        let v = core::array::from_fn(|c| {
            core::array::from_fn(|a| Vec4::new(lane(0).v[c][a], lane(1).v[c][a], lane(2).v[c][a], lane(3).v[c][a]))
        });
        let mut ids = [prims[0]; 4];
        ids[..prims.len()].copy_from_slice(prims);
        Self { v, prims: ids, len: prims.len() as u32 }
    }

    /// Project the four triangles through `p`'s apex and hand the ones that may hide part of the
    /// rectangle `[lo, hi]` to `keep`: a lane is dropped when all its corners lie before `touch`, or
    /// all past `far`, or all in `[near, far]` and its projection's bounding rectangle misses
    /// `[lo, hi]`, or, reaching out of `[near, far]`, a plane keeps it beside the beam
    /// ([`beside_planes`]).
    #[inline]
    pub(crate) fn survivors(&self, p: &Projector, lo: Vec2, hi: Vec2, keep: &mut impl FnMut(Survivor)) {
        let splat = Vec4::splat;
        let (mut h, mut x, mut y) = ([Vec4::ZERO; 3], [Vec4::ZERO; 3], [Vec4::ZERO; 3]);
        let mut corners = [[Vec4::ZERO; 3]; 3];
        for c in 0..3 {
            let w = [self.v[c][0] - splat(p.apex.x), self.v[c][1] - splat(p.apex.y), self.v[c][2] - splat(p.apex.z)];
            corners[c] = w;
            let dot = |a: Vec3| w[0] * a.x + w[1] * a.y + w[2] * a.z;
            h[c] = dot(p.normal);
            let s = splat(p.distance) / h[c];
            x[c] = splat(p.apex_uv.x) + dot(p.u) * s;
            y[c] = splat(p.apex_uv.y) + dot(p.v) * s;
        }
        let (near, far) = (splat(p.near), splat(p.far));
        let touch = splat(p.touch);
        let before = h[0].cmplt(touch) & h[1].cmplt(touch) & h[2].cmplt(touch);
        let past = h[0].cmpgt(far) & h[1].cmpgt(far) & h[2].cmpgt(far);
        let inside = |h: Vec4| h.cmpge(near) & h.cmple(far);
        let in_range = inside(h[0]) & inside(h[1]) & inside(h[2]);
        let (min_x, max_x) = (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]));
        let (min_y, max_y) = (y[0].min(y[1]).min(y[2]), y[0].max(y[1]).max(y[2]));
        let beside =
            max_x.cmplt(splat(lo.x)) | max_y.cmplt(splat(lo.y)) | min_x.cmpgt(splat(hi.x)) | min_y.cmpgt(splat(hi.y));
        // NaN depths (a corner at the apex's plane is not NaN: it is infinite) fail every compare
        // and are kept for the exact path, which rejects them.
        let mut dropped = (before | past | (in_range & beside)).bitmask();
        // Lanes reaching out of the depth range: dropped when a plane keeps them beside the beam.
        let reaching = !dropped & !in_range.bitmask() & ((1 << self.len) - 1);
        if reaching != 0 {
            dropped |= beside_planes(&corners, p, lo, hi).bitmask() & reaching;
        }
        let projected = in_range.bitmask();
        for lane in 0..self.len as usize {
            if dropped & (1 << lane) != 0 {
                continue;
            }
            let corners =
                (projected & (1 << lane) != 0).then(|| core::array::from_fn(|c| Vec2::new(x[c][lane], y[c][lane])));
            keep(Survivor { prim: self.prims[lane], projected: corners });
        }
    }
}

/// `ShadowBeam::beside` for four triangles (corners `w[corner][axis]`, relative to the apex): the
/// lanes that a plane through the apex and one of their edges, or their own plane at the far
/// plane, keeps out of the pyramid through the rectangle `[lo, hi]` of the light's plane with the
/// rectangle beyond `p.eps`.
fn beside_planes(w: &[[Vec4; 3]; 3], p: &Projector, lo: Vec2, hi: Vec2) -> BVec4A {
    let splat = Vec4::splat;
    let cross = |a: &[Vec4; 3], b: &[Vec4; 3]| {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    };
    let dot = |n: &[Vec4; 3], a: Vec3| n[0] * a.x + n[1] * a.y + n[2] * a.z;
    let dot4 = |n: &[Vec4; 3], a: &[Vec4; 3]| n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
    // `k + g·x` exceeds the tolerance over the whole rectangle: at its corner where it is least.
    let clear = |k: Vec4, gx: Vec4, gy: Vec4| {
        let lx = Vec4::select(gx.cmpgt(Vec4::ZERO), splat(lo.x), splat(hi.x));
        let ly = Vec4::select(gy.cmpgt(Vec4::ZERO), splat(lo.y), splat(hi.y));
        // `d > eps·|g|` without a square root: d > 0 and d² > eps²·|g|².
        let d = k + gx * lx + gy * ly;
        d.cmpgt(Vec4::ZERO) & (d * d).cmpgt(splat(p.eps * p.eps) * (gx * gx + gy * gy))
    };
    let mut out = BVec4A::splat(false);
    for i in 0..3 {
        let n = cross(&w[i], &w[(i + 1) % 3]);
        // Positive away from the triangle.
        let sign = Vec4::select(dot4(&n, &w[(i + 2) % 3]).cmpgt(Vec4::ZERO), splat(-1.0), splat(1.0));
        out |= clear(dot(&n, p.origin) * sign, dot(&n, p.u) * sign, dot(&n, p.v) * sign);
    }
    let sub = |a: &[Vec4; 3], b: &[Vec4; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let m = cross(&sub(&w[1], &w[0]), &sub(&w[2], &w[0]));
    let e = dot4(&m, &w[0]);
    let sign = Vec4::select(e.cmplt(Vec4::ZERO), splat(-1.0), splat(1.0));
    let e = e * sign;
    let far = clear(e / (1.0 - DEPTH_EPS) - dot(&m, p.origin) * sign, -dot(&m, p.u) * sign, -dot(&m, p.v) * sign);
    out | (far & e.cmpgt(Vec4::ZERO))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shadow_beam::visible::light_beam;
    use crate::render::shadow_beam::{ShadowBeam, ShadowScratch};

    /// Every triangle the packet test drops hides nothing of the beam by the exact path: on random
    /// triangles reaching behind the point and past the light (the unit square at z = 2 seen from
    /// the origin), and the packet's planes drop most of those that miss it.
    #[test]
    fn dropped_lanes_hide_nothing() {
        let light = [
            Vec3::new(-0.5, -0.5, 2.0),
            Vec3::new(0.5, -0.5, 2.0),
            Vec3::new(0.5, 0.5, 2.0),
            Vec3::new(-0.5, 0.5, 2.0),
        ];
        let beam = light_beam(Vec3::ZERO, &light, -Vec3::Z).unwrap();
        let mut s = 7u32;
        let mut r = move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        let tris: Vec<Triangle> = (0..4000)
            .map(|_| {
                let v = |r: &mut dyn FnMut() -> f32| Vec3::new(3.0 * r(), 3.0 * r(), 1.0 + 2.0 * r());
                Triangle::new(v(&mut r), v(&mut r), v(&mut r))
            })
            .collect();
        let (mut dropped, mut missing) = (0, 0);
        for (k, chunk) in tris.chunks(4).enumerate() {
            let prims: Vec<u32> = (0..chunk.len() as u32).map(|i| 4 * k as u32 + i).collect();
            let mut scratch = ShadowScratch::default();
            let traced = ShadowBeam::new(&beam, &mut scratch);
            let (lo, hi) = traced.bounds();
            let mut kept = Vec::new();
            Packet::new(&tris, &prims).survivors(&traced.projector(), lo, hi, &mut |s| kept.push(s.prim));
            for &prim in &prims {
                let mut scratch = ShadowScratch::default();
                let mut alone = ShadowBeam::new(&beam, &mut scratch);
                let hit = alone.occlude(&tris[prim as usize]);
                missing += usize::from(!hit);
                if !kept.contains(&prim) {
                    dropped += 1;
                    assert!(!hit, "{:?} was dropped but hides part of the light", tris[prim as usize]);
                }
            }
        }
        assert!(dropped > missing / 2, "dropped {dropped} of {missing} that hide nothing");
    }
}
