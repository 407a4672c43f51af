//! The 8-wide CPU layout: nodes of eight children whose boxes a ray tests together (AVX2 or
//! AVX-512 where the CPU has them, picked at run time; two four-lane halves elsewhere), leaves of
//! triangles in blocks of four ([`Tri4`]) intersected four at a time by the watertight test, and
//! a builder that bins straight into eight-wide nodes ([`Bvh8::build`]).
//!
//! Every kernel answers what the scalar watertight test answers triangle by triangle: the box
//! tests only add candidates (their far distance is widened by a few ulps, Ize 2013) and the
//! triangle lanes repeat the scalar operations exactly.

mod build;
mod collapse;
mod gather;
mod kernel;
mod layout;
mod leaf;
mod node;
mod optimal;
mod polygon;
mod portable;
mod presplit;
mod ray_box;
mod refit;
mod roots;
mod spatial;
mod tree;
mod tri4;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use kernel::Kernel;
pub use node::Node8;
pub use tree::Bvh8;
pub use tri4::Tri4;

use crate::options::BuildOptions;
use crate::stats::TraversalStats;
use crate::traverse::Hit;
use beam_math::{Ray, Triangle};
use std::vec::Vec;
impl Bvh8 {
    /// Build over `triangles`, leaves costed in blocks of four and at most `options.max_leaf`
    /// (≤ 64) triangles. With SAH and [`BuildOptions::collapse`] (the default: the optimal
    /// collapse), a binary tree of small leaves collapsed into eight-wide nodes; else binned splits
    /// taken straight into eight-wide nodes (each node opens its largest child until it has eight,
    /// and with slots left splits the leaves whose cost that lowers). Degenerate triangles are
    /// left out and counted.
    #[must_use]
    pub fn build(triangles: &[Triangle], options: &BuildOptions) -> Self {
        build::build(triangles, options)
    }

    /// The closest hit with `t` in `[0, t_max]`.
    #[must_use]
    pub fn closest_hit(&self, ray: Ray, t_max: f32) -> Option<Hit> {
        self.trace::<false>(ray, t_max, u32::MAX)
    }

    /// True when `ray` hits anything with `t` in `[0, t_max]`. The leaves test the range without
    /// dividing (`t_scaled` against `t_max · det`), so a hit within rounding of `t_max` may count
    /// or not; everywhere else the answer is the scalar watertight test's.
    #[must_use]
    pub fn any_hit(&self, ray: Ray, t_max: f32) -> bool {
        self.trace::<true>(ray, t_max, u32::MAX).is_some()
    }

    /// [`Bvh8::any_hit`] for a ray whose neighbour was stopped by block `last` (of
    /// [`Bvh8::blocks`]): that block is tested first, before any traversal, as shadow rays from one
    /// point to one light are mostly stopped by the same few triangles. The answer is
    /// [`Bvh8::any_hit`]'s, given as the block found hit (`last`, or the first block the traversal
    /// met), to be passed on as the next ray's `last`.
    #[must_use]
    pub fn occluding_block(&self, ray: Ray, t_max: f32, last: Option<u32>) -> Option<u32> {
        self.trace::<true>(ray, t_max, last.unwrap_or(u32::MAX)).map(|h| h.prim)
    }

    /// [`Bvh8::closest_hit`] through the portable kernel, counting child boxes and triangles
    /// tested.
    #[must_use]
    pub fn closest_hit_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit> {
        portable::trace::<false, _>(self, ray, t_max, u32::MAX, stats)
    }

    /// [`Bvh8::any_hit`] through the portable kernel, counting work.
    #[must_use]
    pub fn any_hit_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) -> bool {
        portable::trace::<true, _>(self, ray, t_max, u32::MAX, stats).is_some()
    }

    /// Closest hits of many rays (parallel with the `parallel` feature).
    #[must_use]
    pub fn closest_hits(&self, rays: &[Ray], t_max: f32) -> Vec<Option<Hit>> {
        crate::traverse::map_rays(rays, |r| self.closest_hit(*r, t_max))
    }

    /// Any-hit answers for many rays, each with its own `t_max`.
    #[must_use]
    pub fn any_hits(&self, rays: &[Ray], t_max: &[f32]) -> Vec<bool> {
        crate::traverse::map_segments(rays, t_max, |r, t| self.any_hit(r, t))
    }

    /// The closest hit, or for `ANY` [`ray_box::occluded`] by the first block hit, block `hint`
    /// tested before the traversal (`u32::MAX`: none). The kernels return one `Option<Hit>` in
    /// the caller's slot: a `(bool, Option<Hit>)` copied out of a callee's narrower stores stalled
    /// store forwarding on every ray.
    #[inline]
    fn trace<const ANY: bool>(&self, ray: Ray, t_max: f32, hint: u32) -> Option<Hit> {
        match self.kernel {
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 | Kernel::Avx512 if self.stack_need + 8 <= x86::STACK_CAPACITY => {
                x86::trace::<ANY>(self, ray, t_max, hint)
            }
            _ => portable::trace::<ANY, ()>(self, ray, t_max, hint, &mut ()),
        }
    }
}

#[cfg(test)]
mod tests;
