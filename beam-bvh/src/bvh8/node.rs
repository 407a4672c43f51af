//! The eight-wide node: eight child boxes in structure-of-arrays form and the references to what
//! they hold.

use beam_math::Aabb;
use beam_math::glam::Vec3;

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

    pub(super) const EMPTY: Self = Self {
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

    pub(super) fn set_bounds(&mut self, i: usize, b: Aabb) {
        for a in 0..3 {
            self.bounds[2 * a][i] = b.min[a];
            self.bounds[2 * a + 1][i] = b.max[a];
        }
    }
}
