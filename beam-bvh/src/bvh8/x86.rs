//! The x86-64 kernels of the 8-wide traversal. A node's eight child boxes take one AVX register
//! per plane; the hit children are ordered by an eight-lane sorting network on keys that carry
//! the entry distance in their high bits and the child's slot in the low three, and all but the
//! nearest are pushed with one vector store; any-hit queries visit the highest hit slot and push
//! the rest as bare references in slot order, gathered to the front of a register by a table of
//! permutations and stored at once (a loop over the hit children cost a mispredicted branch per
//! node). The AVX-512 kernel is the same code compiled with AVX-512 F/VL enabled (EVEX encoding,
//! 32 vector registers, mask registers for compares).
//!
//! The entry and exit distances of the boxes are reduced and compared as the integers their bits
//! spell, as Embree does: an integer `min`/`max` takes one cycle where the float ones take four on
//! Intel cores, and the test is a chain of them. The answer is the float test's: the entry
//! distance includes `+0`, so it is non-negative, and non-negative floats order as their bits; a
//! negative float's bits are a negative integer, below all of those, so an exit distance with a
//! negative term is negative either way and the box is missed either way. The one float the two
//! orders disagree on is `−0` (equal to `+0` as a float, below it as an integer): `t_best` is
//! made `+0` by adding `+0`, and an exit distance comes out `−0` only where a negative exact value
//! underflowed (its constant `c_far` is never `−0`), a box that lies behind the origin. Distances
//! are never NaN ([`FmaBox`]).
//!
//! This module holds the traversal's `unsafe`: aligned loads from nodes, the stack that is not
//! initialised before use, and the calls into `#[target_feature]` code after run-time detection.
#![allow(unsafe_code, reason = "the one module of its crate that holds unsafe blocks, each with a SAFETY comment")]

use super::kernel::Kernel;
use super::leaf::{ShearRay, hinted, visit_leaf};
use super::node::Node8;
use super::ray_box::occluded;
use super::tree::Bvh8;
use crate::traverse::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3A;
use core::arch::x86_64::*;
use core::mem::MaybeUninit;

/// Stack entries of the x86 kernels; trees that need more than this minus 8 (the width of a
/// push) run the portable kernel.
pub(super) const STACK_CAPACITY: usize = 256;

/// Trace with `bvh`'s kernel (AVX2 or AVX-512), as the portable kernel's `trace` does.
pub(super) fn trace<const ANY: bool>(bvh: &Bvh8, ray: Ray, t_max: f32, hint: u32) -> Option<Hit> {
    assert!(bvh.stack_need + 8 <= STACK_CAPACITY, "tree too deep for the x86 kernels");
    match bvh.kernel {
        // SAFETY: `Bvh8::kernel` is `Avx512` only after `Kernel::is_available` (`has_avx512`)
        // found every feature `trace_avx512` enables on this CPU.
        Kernel::Avx512 => unsafe { trace_avx512::<ANY>(bvh, ray, t_max, hint) },
        // SAFETY: likewise, `Avx2` only after `has_avx2`.
        Kernel::Avx2 => unsafe { trace_avx2::<ANY>(bvh, ray, t_max, hint) },
        Kernel::Portable => super::portable::trace::<ANY, ()>(bvh, ray, t_max, hint, &mut ()),
    }
}

/// One traversal kernel: the same body compiled with the features given, so that the AVX-512
/// kernel is more than the AVX2 one called from an AVX-512 function (LLVM does not inline a body
/// this large into a caller with more features).
macro_rules! kernel {
    ($(#[$doc:meta])* $name:ident, $features:literal) => {
        $(#[$doc])*
        #[target_feature(enable = $features)]
        fn $name<const ANY: bool>(bvh: &Bvh8, ray: Ray, t_max: f32, hint: u32) -> Option<Hit> {
            if bvh.nodes.is_empty() || !(t_max >= 0.0) {
                return None;
            }
            let Some(rb) = FmaBox::new(ray, bvh.scale) else {
                return super::portable::trace::<ANY, ()>(bvh, ray, t_max, hint, &mut ());
            };
            let sr = ShearRay::new(ray);
            if ANY && hinted(bvh, hint, &sr, t_max) {
                return Some(occluded(hint));
            }
            let inv = rb.inv.map(|x| _mm256_set1_ps(x));
            let c_near = rb.c_near.map(|x| _mm256_set1_ps(x));
            let c_far = rb.c_far.map(|x| _mm256_set1_ps(x));
            let iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
            let mut slots = Slots::new();
            let mut stack = Stack { slots: &mut slots, len: 0 };
            let mut t_best = t_max;
            let mut best: Option<Hit> = None;
            let mut cur = 0u32;
            loop {
                if cur & Node8::LEAF != 0 {
                    if let Some(block) = visit_leaf::<ANY>(bvh, cur, &sr, &mut t_best, &mut best, |_| {}) {
                        return Some(occluded(block));
                    }
                } else {
                    let n = &bvh.nodes[cur as usize];
                    let near_at = |a: usize| _mm256_fmadd_ps(plane(n, rb.near[a]), inv[a], c_near[a]);
                    let far_at = |a: usize| _mm256_fmadd_ps(plane(n, rb.far[a]), inv[a], c_far[a]);
                    // Distances reduce and compare as integers: see the module's notes.
                    let bits = |v: __m256| _mm256_castps_si256(v);
                    let near = _mm256_max_epi32(
                        _mm256_max_epi32(bits(near_at(0)), bits(near_at(1))),
                        _mm256_max_epi32(bits(near_at(2)), _mm256_setzero_si256()),
                    );
                    let far = _mm256_min_epi32(
                        _mm256_min_epi32(bits(far_at(0)), bits(far_at(1))),
                        _mm256_min_epi32(bits(far_at(2)), _mm256_set1_epi32((t_best + 0.0).to_bits() as i32)),
                    );
                    let miss = _mm256_cmpgt_epi32(near, far);
                    let mask = !(_mm256_movemask_ps(_mm256_castsi256_ps(miss)) as u32) & 0xff;
                    if mask != 0 {
                        if ANY {
                            // Any hit ends the query, so distances are not needed: the highest hit
                            // slot next (a leaf where the node has one: leaves take the last
                            // slots), the others pushed in slot order and popped from the highest
                            // down, as Embree does. On the bench's shadow rays this visits 5–13%
                            // fewer boxes than the lowest slot first. A single hit takes the same
                            // path and pushes nothing: a branch on the count cost 1% of shadow rays.
                            let last = 31 - mask.leading_zeros() as usize;
                            let rest = mask & !(1 << last);
                            cur = next(bvh, n, last);
                            let pending = _mm256_permutevar8x32_epi32(children(n), compaction(rest));
                            stack.push_refs(pending, rest.count_ones() as usize);
                            continue;
                        }
                        let first = mask.trailing_zeros() as usize;
                        let rest = mask & (mask - 1);
                        if rest == 0 {
                            cur = next(bvh, n, first);
                            continue;
                        }
                        // Keys: the distance's bits (non-negative floats order as integers) with
                        // the slot in the low three; misses sort last. Truncated distances are
                        // never above the true ones, so no entry is dropped early.
                        let keys = _mm256_or_si256(_mm256_and_si256(near, _mm256_set1_epi32(!7)), iota);
                        let keys = _mm256_blendv_epi8(keys, _mm256_set1_epi32(i32::MAX), miss);
                        if rest & (rest - 1) == 0 {
                            // Two hits: continue with the nearer, push the other.
                            let mut k = [0u32; 8];
                            store8(&mut k, keys);
                            let second = rest.trailing_zeros() as usize;
                            let (a, b) = (k[first], k[second]);
                            let (near_key, far_key) = if a <= b { (a, b) } else { (b, a) };
                            stack.push(n.child[(far_key & 7) as usize], far_key & !7);
                            cur = next(bvh, n, (near_key & 7) as usize);
                            continue;
                        }
                        // More: the nearest by a min-reduction (the next node's address does not
                        // wait for the sort), the others sorted and pushed farthest first.
                        let nearest = hmin(keys);
                        cur = next(bvh, n, (nearest & 7) as usize);
                        let sorted = sort8(keys);
                        // `permutevar8x32` reads the low three bits of each index: the slot.
                        let refs = _mm256_permutevar8x32_epi32(children(n), sorted);
                        let dists = _mm256_and_si256(sorted, _mm256_set1_epi32(!7));
                        let count = mask.count_ones() as i32;
                        // Lane i takes entry count − 1 − i: entries count − 1 down to 1.
                        let rev = _mm256_sub_epi32(_mm256_set1_epi32(count - 1), iota);
                        let (r, d) = (_mm256_permutevar8x32_epi32(refs, rev), _mm256_permutevar8x32_epi32(dists, rev));
                        stack.push8(r, d, count as usize - 1);
                        continue;
                    }
                }
                // Pop the nearest pending node still in front of the best hit (any-hit queries
                // push no distances: every pending node is still to be visited).
                if ANY {
                    cur = stack.pop_ref()?;
                    continue;
                }
                loop {
                    let Some((r, d)) = stack.pop() else {
                        return best;
                    };
                    if f32::from_bits(d) <= t_best {
                        cur = r;
                        break;
                    }
                }
            }
        }
    };
}

kernel!(
    /// AVX2 with FMA, POPCNT and BMI1.
    trace_avx2,
    "avx2,fma,popcnt,bmi1"
);
kernel!(
    /// AVX-512 F/VL besides.
    trace_avx512,
    "avx2,fma,popcnt,bmi1,avx512f,avx512vl"
);

/// Per-ray constants of the box test: one fused multiply-add per plane, `t = b·inv + c`. `c` is
/// `−o·inv` moved outwards by a margin (`c_near` down, `c_far` up) that covers every rounding on
/// the way, so a computed near distance never exceeds the exact one and a far one never falls
/// short: the test only adds boxes, as watertight traversal needs. Direction components below
/// 2^-60 count as ±2^-60 (the margin covers that too) and rays with an infinite component run
/// the portable kernel, so no distance is NaN.
#[derive(Clone, Copy, Debug)]
struct FmaBox {
    inv: [f32; 3],
    c_near: [f32; 3],
    c_far: [f32; 3],
    /// Byte offsets in [`Node8::bounds`] of the plane of each axis the ray meets first and last.
    near: [usize; 3],
    far: [usize; 3],
}

impl FmaBox {
    /// `None` for a ray whose constants overflow (an origin beyond 2^60 times the scene, NaN).
    /// `scale` bounds every coordinate of the tree's boxes.
    #[inline(always)]
    fn new(ray: Ray, scale: f32) -> Option<Self> {
        const TINY: f32 = 1.0 / (1u64 << 60) as f32;
        // Eight units of rounding of the largest term, `(|b| + |o|)·|inv|`, with b any plane.
        const MARGIN: f32 = 1.0 / (1 << 21) as f32;
        let d = Vec3A::from(ray.direction);
        let d = Vec3A::select(d.abs().cmplt(Vec3A::splat(TINY)), Vec3A::splat(TINY).copysign(d), d);
        // The plane offsets take the signs of `d`, which `inv` has: the first node's loads, which
        // wait for the offsets, need not wait for the division.
        let negative = d.is_negative_bitmask() as usize;
        let o = Vec3A::from(ray.origin);
        let inv = d.recip();
        // `−o·inv ∓ margin` with `margin = (scale + |o|)·|inv|·MARGIN`, computed as `−(o ± m)·inv`
        // where `m = (scale + |o|)·MARGIN` takes the sign of `d` (that of `inv`): the origins
        // moved out are ready before the division is, which leaves one product after it (this
        // prologue's latency is paid by every ray). With ε = 2⁻²⁴ the computed near distance is
        // `(1+δ)(1+δ')(t − (m + E)/d)` (the rounding of the fused multiply-add and of `inv`) with
        // `|E| ≤ 2ε(|o| + |m|)` (the rounding of `o ± m` and of the product): it stays below `t`
        // while `2ε·|t| ≤ (|m| − |E|)/|d|`, and `|t| ≤ (scale + |o|)/|d|` against `|m| − |E| ≈
        // 6ε·(scale + |o|)`. The far distance likewise.
        let m = ((scale + o.abs()) * MARGIN).copysign(d);
        let (c_near, c_far) = (-((o + m) * inv), -((o - m) * inv));
        // Both constants are finite where their difference is (not ∞ − ∞, nor NaN). An infinite
        // direction component (`inv` 0) would make an unused slot's planes ∞·0 = NaN: portable.
        let finite = (c_far - c_near + inv.abs()).cmplt(Vec3A::splat(f32::INFINITY));
        if !(finite & inv.cmpne(Vec3A::ZERO)).all() {
            return None;
        }
        let side = |a: usize| (negative >> a) & 1;
        Some(Self {
            inv: inv.to_array(),
            c_near: c_near.to_array(),
            c_far: c_far.to_array(),
            near: core::array::from_fn(|a| 32 * (2 * a + side(a))),
            far: core::array::from_fn(|a| 32 * (2 * a + 1 - side(a))),
        })
    }
}

/// The reference in slot `s` of `n`, prefetched: for an inner child computed from
/// [`Node8::base`] (a branch, not a select, so that the next node's loads need not wait for a
/// load of the reference).
#[inline]
#[target_feature(enable = "sse")]
fn next(bvh: &Bvh8, n: &Node8, s: usize) -> u32 {
    let r = if s < n.inner as usize {
        debug_assert_eq!(n.child[s], n.base.wrapping_add(s as u32));
        n.base.wrapping_add(s as u32)
    } else {
        n.child[s]
    };
    prefetch(bvh, r);
    r
}

/// Fetch the four cache lines of node `r`, or for a leaf the three of its first block, while the
/// current node is finished (Embree prefetches leaves too).
#[inline]
#[target_feature(enable = "sse")]
fn prefetch(bvh: &Bvh8, r: u32) {
    // A prefetch reads nothing and never faults: any address will do.
    if r & Node8::LEAF == 0 {
        let p = bvh.nodes.as_ptr().wrapping_add(r as usize).cast::<i8>();
        for line in 0..4 {
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(64 * line));
        }
    } else {
        let p = bvh.blocks.as_ptr().wrapping_add(Node8::leaf_blocks(r).0).cast::<i8>();
        for line in 0..3 {
            _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(64 * line));
        }
    }
}

/// The plane at byte `offset` (32·k, k < 6, as [`FmaBox`] makes them) of the eight child boxes
/// of `n`.
#[inline]
#[target_feature(enable = "avx")]
fn plane(n: &Node8, offset: usize) -> __m256 {
    debug_assert!(offset < 6 * 32 && offset % 32 == 0);
    // SAFETY: `offset` is 32·k with `k < 6` (`FmaBox::near`/`far` hold `32·(2a + side)` with
    // `a < 3`, `side ≤ 1`), so the row is eight f32 inside `n.bounds`, at offset 32·k of a 64-byte
    // aligned `Node8`: 32-byte aligned for the load.
    unsafe { _mm256_load_ps(n.bounds.as_ptr().cast::<u8>().add(offset).cast::<f32>()) }
}

/// The eight child references of `n`.
#[inline]
#[target_feature(enable = "avx")]
fn children(n: &Node8) -> __m256i {
    // SAFETY: `child` is eight u32 at offset 192 of a 64-byte aligned `Node8`: 32-byte aligned.
    unsafe { _mm256_load_si256(n.child.as_ptr().cast()) }
}

/// The smallest of eight signed integers.
#[inline]
#[target_feature(enable = "avx2")]
fn hmin(v: __m256i) -> u32 {
    let v = _mm256_min_epi32(v, _mm256_permute2x128_si256::<1>(v, v));
    let v = _mm256_min_epi32(v, _mm256_shuffle_epi32::<0b01_00_11_10>(v));
    let v = _mm256_min_epi32(v, _mm256_shuffle_epi32::<0b10_11_00_01>(v));
    _mm256_cvtsi256_si32(v) as u32
}

/// Lane indices that gather the set bits of an eight-bit mask to the front, in ascending order
/// (the rest zero), one row of eight bytes per mask.
static COMPACT: [[u8; 8]; 256] = {
    let mut t = [[0u8; 8]; 256];
    let mut m = 0;
    while m < 256 {
        let (mut bit, mut k) = (0, 0);
        while bit < 8 {
            if m >> bit & 1 != 0 {
                t[m][k] = bit as u8;
                k += 1;
            }
            bit += 1;
        }
        m += 1;
    }
    t
};

/// The permutation that moves the lanes set in `mask` (< 256) to the front, in ascending order.
#[inline]
#[target_feature(enable = "avx2")]
fn compaction(mask: u32) -> __m256i {
    let row = &COMPACT[mask as usize & 0xff];
    // SAFETY: `row` is eight bytes (an unaligned 64-bit load).
    _mm256_cvtepu8_epi32(unsafe { _mm_loadl_epi64(row.as_ptr().cast()) })
}

/// Store eight lanes.
#[inline]
#[target_feature(enable = "avx")]
fn store8(out: &mut [u32; 8], v: __m256i) {
    // SAFETY: `out` is eight u32 (an unaligned store).
    unsafe { _mm256_storeu_si256(out.as_mut_ptr().cast(), v) }
}

/// Sort eight signed integers ascending: a bitonic network of six compare-exchange stages.
#[inline]
#[target_feature(enable = "avx2")]
fn sort8(v: __m256i) -> __m256i {
    // Compare-exchange each lane with `partner`; lanes set in `UPPER` keep the larger value.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn cx<const UPPER: i32>(v: __m256i, partner: __m256i) -> __m256i {
        _mm256_blend_epi32::<UPPER>(_mm256_min_epi32(v, partner), _mm256_max_epi32(v, partner))
    }
    let pairs = |v| cx::<0b1010_1010>(v, _mm256_shuffle_epi32::<0b10_11_00_01>(v));
    let v = pairs(v);
    let v = cx::<0b1100_1100>(v, _mm256_shuffle_epi32::<0b00_01_10_11>(v));
    let v = pairs(v);
    let v = cx::<0b1111_0000>(v, _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(7, 6, 5, 4, 3, 2, 1, 0)));
    let v = cx::<0b1100_1100>(v, _mm256_shuffle_epi32::<0b01_00_11_10>(v));
    pairs(v)
}

/// Storage of the traversal stack: node references and distance bits, written before they are
/// read, never initialised as a whole (a 2 KiB memset per ray would cost more than a shallow
/// traversal).
struct Slots {
    refs: [MaybeUninit<u32>; STACK_CAPACITY],
    dists: [MaybeUninit<u32>; STACK_CAPACITY],
}

impl Slots {
    #[inline(always)]
    fn new() -> Self {
        Self { refs: [MaybeUninit::uninit(); STACK_CAPACITY], dists: [MaybeUninit::uninit(); STACK_CAPACITY] }
    }
}

/// The traversal stack. Its length lives apart from the slots: next to the store of `len = 0`,
/// LLVM merges the uninitialised arrays into one zeroing memset.
struct Stack<'a> {
    slots: &'a mut Slots,
    len: usize,
}

impl Stack<'_> {
    #[inline(always)]
    fn push(&mut self, r: u32, d: u32) {
        self.slots.refs[self.len] = MaybeUninit::new(r);
        self.slots.dists[self.len] = MaybeUninit::new(d);
        self.len += 1;
    }

    /// Push the first `count` (≤ 8) lanes of `r` without distances (read back by
    /// [`Stack::pop_ref`] only).
    #[inline]
    #[target_feature(enable = "avx")]
    fn push_refs(&mut self, r: __m256i, count: usize) {
        assert!(self.len + 8 <= STACK_CAPACITY && count <= 8);
        // SAFETY: `len + 8 ≤ STACK_CAPACITY` (checked above): the 32-byte store stays inside the
        // array, whose elements have the layout of `u32`.
        unsafe { _mm256_storeu_si256(self.slots.refs.as_mut_ptr().add(self.len).cast(), r) };
        self.len += count;
    }

    /// Pop a reference pushed by [`Stack::push_refs`].
    #[inline(always)]
    fn pop_ref(&mut self) -> Option<u32> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: every slot below the old `len` was written by `push_ref` before `len` grew
        // past it.
        Some(unsafe { self.slots.refs[self.len].assume_init() })
    }

    /// Push the first `count` (< 8) lanes of `r` and `d`.
    #[inline]
    #[target_feature(enable = "avx")]
    fn push8(&mut self, r: __m256i, d: __m256i, count: usize) {
        assert!(self.len + 8 <= STACK_CAPACITY && count < 8);
        // SAFETY: `len + 8 ≤ STACK_CAPACITY` (checked above): both 32-byte stores stay inside the
        // arrays, whose elements have the layout of `u32`.
        unsafe {
            _mm256_storeu_si256(self.slots.refs.as_mut_ptr().add(self.len).cast(), r);
            _mm256_storeu_si256(self.slots.dists.as_mut_ptr().add(self.len).cast(), d);
        }
        self.len += count;
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<(u32, u32)> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: every slot below the old `len` was written by `push` or `push8` before `len`
        // grew past it.
        Some(unsafe { (self.slots.refs[self.len].assume_init(), self.slots.dists[self.len].assume_init()) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh8::kernel::has_avx2;

    #[test]
    fn sort8_sorts() {
        if !has_avx2() {
            return;
        }
        let mut s = 12345u32;
        for _ in 0..10_000 {
            let mut v = [0i32; 8];
            for x in &mut v {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                *x = (s >> 20) as i32;
            }
            // SAFETY: AVX2 was detected above.
            let sorted: [i32; 8] = unsafe { sort_array(v) };
            let mut want = v;
            want.sort_unstable();
            assert_eq!(sorted, want);
        }
    }

    /// The table's permutation moves exactly the set lanes to the front, in ascending order.
    #[test]
    fn compaction_gathers_the_set_lanes() {
        if !has_avx2() {
            return;
        }
        for mask in 0..256u32 {
            // SAFETY: AVX2 was detected above.
            let got = unsafe { compact_array(mask) };
            let want: Vec<i32> = (0..8).filter(|i| mask >> i & 1 != 0).map(|i| 10 + i).collect();
            assert_eq!(&got[..want.len()], &want[..], "mask {mask:08b}");
        }
    }

    #[target_feature(enable = "avx2")]
    fn compact_array(mask: u32) -> [i32; 8] {
        let mut out = [0i32; 8];
        let v = _mm256_setr_epi32(10, 11, 12, 13, 14, 15, 16, 17);
        // SAFETY: `out` is eight i32 (an unaligned store).
        unsafe { _mm256_storeu_si256(out.as_mut_ptr().cast(), _mm256_permutevar8x32_epi32(v, compaction(mask))) };
        out
    }

    #[target_feature(enable = "avx2")]
    fn sort_array(v: [i32; 8]) -> [i32; 8] {
        let mut out = [0i32; 8];
        // SAFETY: `v` and `out` are eight i32 each (unaligned loads and stores).
        unsafe {
            let x = sort8(_mm256_loadu_si256(v.as_ptr().cast()));
            _mm256_storeu_si256(out.as_mut_ptr().cast(), x);
        }
        out
    }
}
