//! The 8-wide BVH's data: nodes, triangle blocks and what a query needs to pick its kernel. The
//! builder and the queries live beside it ([`super::build`], [`super::portable`]).

use super::kernel::Kernel;
use super::node::Node8;
use super::tri4::Tri4;
use beam_math::Aabb;
use std::vec::Vec;

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
    pub(super) kernel: Kernel,
    /// The largest magnitude of any coordinate of `bounds` (the x86 kernels' rounding margin).
    pub(super) scale: f32,
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
    /// Set `bounds` (and what depends on it).
    pub(super) fn set_tree_bounds(&mut self, bounds: Aabb) {
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
}
