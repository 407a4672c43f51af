//! What every traversal kernel shares per ray: the box test's constants and the any-hit answer.

use crate::traverse::Hit;
use beam_math::Ray;
use beam_math::glam::Vec4;

/// What an any-hit traversal returns for a ray that hits block `block` (of [`Bvh8::blocks`]): the
/// block in `prim`, the other fields meaning nothing.
///
/// [`Bvh8::blocks`]: super::Bvh8::blocks
#[inline(always)]
pub(super) fn occluded(block: u32) -> Hit {
    Hit { prim: block, t: 0.0, u: 0.0, v: 0.0 }
}

/// Per-ray constants of the box tests: origin, reciprocal direction for near planes and a
/// widened one for far planes, and which plane of each axis the ray meets first (`near[a]`
/// indexes [`Node8::bounds`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayBox {
    pub origin: [f32; 3],
    pub inv: [f32; 3],
    pub inv_far: [f32; 3],
    pub near: [usize; 3],
    pub far: [usize; 3],
}

/// Far distances are widened by this factor so that rounding never loses a box the ray touches
/// (Ize, "Robust BVH ray traversal", 2013: the far planes' reciprocal times 1 + 2γ₃, rounded up).
const ROBUST: f32 = 1.000_000_5;

impl RayBox {
    #[inline(always)]
    pub(super) fn new(ray: Ray) -> Self {
        // One four-lane division, each lane rounded as `1.0 / d` is.
        let inv = (Vec4::ONE / ray.direction.extend(1.0)).truncate();
        let side = |a: usize| usize::from(inv[a].is_sign_negative());
        Self {
            origin: ray.origin.to_array(),
            inv: inv.to_array(),
            inv_far: (inv * ROBUST).to_array(),
            near: core::array::from_fn(|a| 2 * a + side(a)),
            far: core::array::from_fn(|a| 2 * a + 1 - side(a)),
        }
    }
}
