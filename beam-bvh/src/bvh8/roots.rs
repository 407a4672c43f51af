//! What the collapses into eight-wide nodes share: their cost model ([`NODE_COST`], [`cost_area`])
//! and the interface of a strategy that picks each node's children ([`Roots`]). The greedy
//! collapse ([`super::collapse`]) and the optimal one ([`super::optimal`]) both build on it.

use beam_math::Aabb;
use beam_math::glam::DVec3;
use std::vec::Vec;

/// An eight-wide node's test costs as much as this many block tests in the collapse's cost model
/// (times [`BuildOptions::traversal_cost`](crate::options::BuildOptions::traversal_cost), a binary node's):
/// with these kernels 1.5 gave rays of every kind faster than 1 on the conference room (shadow
/// rays 3.6%) and the same on Sponza; 1.75 gives Sponza's shadow rays 1–3% more than 1.5 and
/// the conference room the same (2.0 no more than 1.75; 3.0 less than 1.5).
pub(super) const NODE_COST: f32 = 1.75;

/// The surface area of `b` as the collapses cost it: in `f64`, from the corners, so that it is
/// finite for every box of finite corners. In `f32` a box wider than about 10¹⁹ (one vertex of a
/// mesh at 10³⁰) has an infinite area, every cost above it is infinite too, and no choice between
/// them means anything.
pub(super) fn cost_area(b: Aabb) -> f64 {
    let e = (b.max.as_dvec3() - b.min.as_dvec3()).max(DVec3::ZERO);
    2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
}

/// How a collapse picks the children of eight-wide nodes among the binary tree's subtrees.
pub(super) trait Roots {
    /// Whether the subtree of binary node `k`, as a child slot, becomes one leaf.
    fn is_leaf(&self, k: usize) -> bool;
    /// Push the two to eight binary roots that become the children of the eight-wide node made
    /// for binary node `i` (not a leaf), in the binary tree's left-to-right order.
    fn roots(&self, i: usize, kids: &mut Vec<usize>);
}
