//! A scene's cut-out triangles (glTF `alphaMode` `MASK` and `BLEND`) in a BVH of their own, made
//! when the scene is assembled.

use beam_bvh::{BuildOptions, FlatBvh};
use beam_math::Triangle;

/// A scene's cut-out triangles in a BVH of their own, for beams, which must know where a cut-out
/// may be (beam-cpu's shaft tests).
pub struct CutOutTriangles {
    /// The triangles whose material is a cut-out.
    pub triangles: Vec<Triangle>,
    /// Their BVH.
    pub bvh: FlatBvh,
}

impl CutOutTriangles {
    /// The triangles of `triangles` whose `cut_out` is true; `None` when there are none.
    pub(super) fn of(triangles: &[Triangle], cut_out: impl Fn(usize) -> bool) -> Option<Self> {
        let triangles: Vec<Triangle> = (0..triangles.len()).filter(|&i| cut_out(i)).map(|i| triangles[i]).collect();
        (!triangles.is_empty()).then(|| Self { bvh: FlatBvh::build(&triangles, &BuildOptions::sah()), triangles })
    }
}
