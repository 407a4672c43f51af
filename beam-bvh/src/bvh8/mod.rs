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
mod layout;
mod leaf;
mod optimal;
mod polygon;
mod portable;
mod presplit;
mod refit;
mod spatial;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use leaf::Tri4;

use crate::options::BuildOptions;
use crate::stats::TraversalStats;
use crate::traverse::Hit;
use beam_math::glam::{Vec3, Vec4};
use beam_math::{Aabb, Ray, Triangle};
use core::fmt;
use std::vec::Vec;

/// A node of eight children in structure-of-arrays form: `bounds[2·axis]` holds the children's
/// box minima along `axis`, `bounds[2·axis + 1]` their maxima. Unused slots have an empty box
/// (`+∞` minima, `−∞` maxima), which no ray enters.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct Node8 {
    /// Child box planes: min x, max x, min y, max y, min z, max z; one lane per child.
    pub bounds: [[f32; 8]; 6],
    /// Child references: an inner node's index, or a leaf ([`Node8::LEAF`] set) as its first block
    /// (low 27 bits) and its number of blocks minus one (bits 27–30); [`Node8::UNUSED`] for none.
    pub child: [u32; 8],
    /// Triangles of a leaf child; 0 for an inner child or an unused slot.
    pub tris: [u8; 8],
    /// Index of the first inner child: the node's inner children take slots `0..inner` and
    /// consecutive indices from `base` (`child[s] == base + s`), so a kernel can find the next
    /// node without loading its reference. Every build sets it; `inner == 0` is always valid (the
    /// kernels then load every reference), other values that break this rule give wrong answers
    /// (never undefined behaviour).
    pub base: u32,
    /// Number of inner children (slots `0..inner`); leaves follow them, unused slots come last.
    pub inner: u8,
    /// Padding to four cache lines.
    pub pad: [u8; 19],
}

const _: () = assert!(size_of::<Node8>() == 256);

impl Node8 {
    /// The flag of a leaf reference.
    pub const LEAF: u32 = 1 << 31;
    /// An unused slot's reference.
    pub const UNUSED: u32 = u32::MAX;
    /// Most blocks of four triangles in one leaf.
    pub const MAX_LEAF_BLOCKS: usize = 16;

    const EMPTY: Self = Self {
        bounds: [
            [f32::INFINITY; 8],
            [f32::NEG_INFINITY; 8],
            [f32::INFINITY; 8],
            [f32::NEG_INFINITY; 8],
            [f32::INFINITY; 8],
            [f32::NEG_INFINITY; 8],
        ],
        child: [Self::UNUSED; 8],
        tris: [0; 8],
        base: 0,
        inner: 0,
        pad: [0; 19],
    };

    /// The reference of a leaf of `blocks` blocks starting at block `first`.
    #[must_use]
    pub fn leaf_ref(first: u32, blocks: u32) -> u32 {
        assert!(first < 1 << 27, "more than 2^27 triangle blocks");
        debug_assert!((1..=Self::MAX_LEAF_BLOCKS as u32).contains(&blocks));
        Self::LEAF | ((blocks - 1) << 27) | first
    }

    /// First block and number of blocks of a leaf reference.
    #[must_use]
    #[inline(always)]
    pub fn leaf_blocks(r: u32) -> (usize, usize) {
        ((r & ((1 << 27) - 1)) as usize, ((r >> 27) & 15) as usize + 1)
    }

    /// Box of child `i`.
    #[must_use]
    pub fn child_bounds(&self, i: usize) -> Aabb {
        let b = &self.bounds;
        Aabb::new(Vec3::new(b[0][i], b[2][i], b[4][i]), Vec3::new(b[1][i], b[3][i], b[5][i]))
    }

    fn set_bounds(&mut self, i: usize, b: Aabb) {
        for a in 0..3 {
            self.bounds[2 * a][i] = b.min[a];
            self.bounds[2 * a + 1][i] = b.max[a];
        }
    }
}

/// Which traversal code runs: the widest the CPU supports, found at run time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// Two four-lane halves through glam (SSE2 on x86-64, NEON on AArch64, scalar elsewhere).
    Portable,
    /// AVX2 (x86-64).
    Avx2,
    /// AVX-512 F/VL on eight lanes (x86-64).
    Avx512,
}

impl Kernel {
    /// The widest kernel this CPU runs.
    #[must_use]
    pub fn detect() -> Self {
        [Kernel::Avx512, Kernel::Avx2].into_iter().find(|k| k.is_available()).unwrap_or(Kernel::Portable)
    }

    /// Whether this CPU runs the kernel.
    #[must_use]
    pub fn is_available(self) -> bool {
        match self {
            Kernel::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 => x86::has_avx2(),
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => x86::has_avx512(),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }
}

impl fmt::Display for Kernel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Kernel::Portable if cfg!(target_arch = "x86_64") => "sse2 (2×4 lanes)",
            Kernel::Portable if cfg!(target_arch = "aarch64") => "neon (2×4 lanes)",
            Kernel::Portable => "scalar (2×4 lanes)",
            Kernel::Avx2 => "avx2 (8 lanes)",
            Kernel::Avx512 => "avx512 (8 lanes)",
        })
    }
}

/// An 8-wide BVH with its triangles copied into blocks of four in leaf order.
#[derive(Clone, Debug)]
pub struct Bvh8 {
    /// Nodes; node 0 is the root (its children are the tree's top).
    pub nodes: Vec<Node8>,
    /// Triangle blocks in leaf order.
    pub blocks: Vec<Tri4>,
    /// Input index of each block lane (`4·block + lane`); `u32::MAX` for an unused lane.
    pub prims: Vec<u32>,
    /// Bounds of the whole tree.
    pub bounds: Aabb,
    /// Degenerate triangles left out.
    pub degenerate: usize,
    /// Number of input triangles.
    pub input_triangles: usize,
    /// Most entries a traversal keeps on its stack.
    pub stack_need: usize,
    kernel: Kernel,
    /// The largest magnitude of any coordinate of `bounds` (the x86 kernels' rounding margin).
    scale: f32,
}

impl Default for Bvh8 {
    fn default() -> Self {
        Self {
            nodes: Vec::new(),
            blocks: Vec::new(),
            prims: Vec::new(),
            bounds: Aabb::EMPTY,
            degenerate: 0,
            input_triangles: 0,
            stack_need: 0,
            kernel: Kernel::detect(),
            scale: 0.0,
        }
    }
}

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

    /// Set `bounds` (and what depends on it).
    fn set_tree_bounds(&mut self, bounds: Aabb) {
        self.bounds = bounds;
        self.scale = bounds.min.abs().max(bounds.max.abs()).max_element();
    }

    /// The kernel queries run with.
    #[must_use]
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Run queries with `kernel` if this CPU has it (else keep the current one); returns whether it
    /// is now in use.
    pub fn set_kernel(&mut self, kernel: Kernel) -> bool {
        if kernel.is_available() {
            self.kernel = kernel;
        }
        self.kernel == kernel
    }

    /// The closest hit with `t` in `[0, t_max]`.
    #[must_use]
    pub fn closest_hit(&self, ray: Ray, t_max: f32) -> Option<Hit> {
        self.trace::<false>(ray, t_max)
    }

    /// True when `ray` hits anything with `t` in `[0, t_max]`. The leaves test the range without
    /// dividing (`t_scaled` against `t_max · det`), so a hit within rounding of `t_max` may count
    /// or not; everywhere else the answer is the scalar watertight test's.
    #[must_use]
    pub fn any_hit(&self, ray: Ray, t_max: f32) -> bool {
        self.trace::<true>(ray, t_max).is_some()
    }

    /// [`Bvh8::closest_hit`] through the portable kernel, counting child boxes and triangles
    /// tested.
    #[must_use]
    pub fn closest_hit_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit> {
        portable::trace::<false, _>(self, ray, t_max, stats)
    }

    /// [`Bvh8::any_hit`] through the portable kernel, counting work.
    #[must_use]
    pub fn any_hit_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) -> bool {
        portable::trace::<true, _>(self, ray, t_max, stats).is_some()
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

    /// The closest hit, or for `ANY` [`OCCLUDED`] when anything is hit (the kernels return one
    /// `Option<Hit>` in the caller's slot: a `(bool, Option<Hit>)` copied out of a callee's
    /// narrower stores stalled store forwarding on every ray).
    #[inline]
    fn trace<const ANY: bool>(&self, ray: Ray, t_max: f32) -> Option<Hit> {
        match self.kernel {
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 | Kernel::Avx512 if self.stack_need + 8 <= x86::STACK_CAPACITY => {
                x86::trace::<ANY>(self, ray, t_max)
            }
            _ => portable::trace::<ANY, ()>(self, ray, t_max, &mut ()),
        }
    }
}

/// What an any-hit traversal returns for a ray that hits something: only `is_some` means
/// anything.
const OCCLUDED: Hit = Hit { prim: u32::MAX, t: 0.0, u: 0.0, v: 0.0 };

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
    pub fn new(ray: Ray) -> Self {
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

#[cfg(test)]
mod tests;
