//! Candidate occluders four at a time: their corners in 4-lane vectors, so that one pass of
//! portable SIMD (glam's `Vec4`: SSE2 on x86-64, NEON on AArch64) projects four triangles onto a
//! shadow beam's light plane and rejects those that lie outside its depth range or beside its
//! remaining pieces before any of them is split (001 §3.4: each vertex projected once per query).

use beam_math::Triangle;
use beam_math::glam::{Vec2, Vec3, Vec4};

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
    /// `[lo, hi]`.
    #[inline]
    pub(crate) fn survivors(&self, p: &Projector, lo: Vec2, hi: Vec2, keep: &mut impl FnMut(Survivor)) {
        let splat = Vec4::splat;
        let (mut h, mut x, mut y) = ([Vec4::ZERO; 3], [Vec4::ZERO; 3], [Vec4::ZERO; 3]);
        for c in 0..3 {
            let w = [self.v[c][0] - splat(p.apex.x), self.v[c][1] - splat(p.apex.y), self.v[c][2] - splat(p.apex.z)];
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
        let dropped = (before | past | (in_range & beside)).bitmask();
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
