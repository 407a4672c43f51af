//! The portable 8-wide traversal: each node's eight boxes as two four-lane halves through glam
//! (SSE2 on x86-64, NEON on AArch64, scalar elsewhere), hit children pushed farthest first
//! (any-hit queries: in the x86 kernels' slot order), leaves through [`visit_leaf`]. It is the
//! fallback where AVX2 is missing, and the kernel that counts work.

use super::leaf::{ShearRay, hinted, visit_leaf};
use super::node::Node8;
use super::ray_box::{RayBox, occluded};
use super::tree::Bvh8;
use crate::stats::Counter;
use crate::traverse::Hit;
use beam_math::Ray;
use beam_math::glam::Vec4;
use std::vec::Vec;

/// Stack entries kept inline; deeper trees use a heap stack.
const INLINE_STACK: usize = 64;

/// Closest hit (`ANY = false`) of `ray` in `[0, t_max]`, or (`ANY = true`) [`occluded`] by the
/// first block found hit there, block `hint` tested first (`u32::MAX`: none).
pub(crate) fn trace<const ANY: bool, C: Counter>(
    bvh: &Bvh8,
    ray: Ray,
    t_max: f32,
    hint: u32,
    c: &mut C,
) -> Option<Hit> {
    if bvh.nodes.is_empty() {
        return None;
    }
    let mut inline = [(0u32, 0.0f32); INLINE_STACK];
    let mut heap = Vec::new();
    let stack: &mut [(u32, f32)] = if bvh.stack_need <= INLINE_STACK {
        &mut inline
    } else {
        heap.resize(bvh.stack_need, (0, 0.0));
        &mut heap
    };
    let rb = RayBox::new(ray);
    let sr = ShearRay::new(ray);
    if ANY && hinted(bvh, hint, &sr, t_max) {
        return Some(occluded(hint));
    }
    let o = rb.origin.map(Vec4::splat);
    let inv = rb.inv.map(Vec4::splat);
    let inv_far = rb.inv_far.map(Vec4::splat);
    let mut t_best = t_max;
    let mut best: Option<Hit> = None;
    let mut sp = 0usize;
    let mut cur = 0u32;
    loop {
        if cur & Node8::LEAF != 0 {
            let count = |k: usize| {
                for l in 0..4 {
                    if bvh.prims[4 * k + l] != u32::MAX {
                        c.triangle();
                    }
                }
            };
            if let Some(block) = visit_leaf::<ANY>(bvh, cur, &sr, &mut t_best, &mut best, count) {
                return Some(occluded(block));
            }
        } else {
            let n = &bvh.nodes[cur as usize];
            let mut near = [0.0f32; 8];
            let mut mask = 0u32;
            let t_far = Vec4::splat(t_best);
            for half in 0..2 {
                let lanes = |k: usize| Vec4::from_slice(&n.bounds[k][4 * half..4 * half + 4]);
                let near_at = |a: usize| (lanes(rb.near[a]) - o[a]) * inv[a];
                let far_at = |a: usize| (lanes(rb.far[a]) - o[a]) * inv_far[a];
                // A NaN distance (origin on a plane of a zero direction component) leaves the
                // accumulator as it is: glam's `max`/`min` return the second operand then.
                let tn = near_at(2).max(near_at(1).max(near_at(0).max(Vec4::ZERO)));
                let tf = far_at(2).min(far_at(1).min(far_at(0).min(t_far)));
                mask |= tn.cmple(tf).bitmask() << (4 * half);
                near[4 * half..4 * half + 4].copy_from_slice(&tn.to_array());
            }
            for i in 0..8 {
                if n.child[i] != Node8::UNUSED {
                    c.node();
                }
            }
            if mask != 0 && ANY {
                // Any hit ends the query: the highest hit slot next, the others popped from the
                // highest down (the x86 kernels' order, and Embree's).
                let last = 31 - mask.leading_zeros() as usize;
                let mut rest = mask & !(1 << last);
                while rest != 0 {
                    let i = rest.trailing_zeros() as usize;
                    rest &= rest - 1;
                    stack[sp] = (n.child[i], 0.0);
                    sp += 1;
                }
                cur = n.child[last];
                continue;
            }
            if mask != 0 {
                // Hit children nearest last, so the nearest is taken next and the rest pushed.
                let mut order = [0usize; 8];
                let mut m = 0;
                let mut bits = mask;
                while bits != 0 {
                    let i = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let mut j = m;
                    while j > 0 && near[order[j - 1]] < near[i] {
                        order[j] = order[j - 1];
                        j -= 1;
                    }
                    order[j] = i;
                    m += 1;
                }
                for &i in &order[..m - 1] {
                    stack[sp] = (n.child[i], near[i]);
                    sp += 1;
                }
                cur = n.child[order[m - 1]];
                continue;
            }
        }
        // Pop the nearest pending node still in front of the best hit.
        loop {
            if sp == 0 {
                return best;
            }
            sp -= 1;
            let (r, d) = stack[sp];
            if d <= t_best {
                cur = r;
                break;
            }
        }
    }
}
