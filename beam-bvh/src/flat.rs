//! The compact CPU layout: 32-byte nodes in depth-first order (left child right after its parent),
//! triangle references by index. The same node is the GPU layout's node (see [`crate::gpu`]).

use crate::build::build;
use crate::options::BuildOptions;
use crate::tree::{Bvh, Node};
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};
use bytemuck::{Pod, Zeroable};
use std::vec::Vec;

/// Traversal stack size; tree depth is bounded below it by the builder.
pub(crate) const STACK_SIZE: usize = 192;

/// A node of the compact layout. Inner nodes have `count == 0`, their left child at the next index
/// and the right child at `right_or_first`; leaves reference `count` triangles from
/// `prims[right_or_first..]`.
///
/// WGSL twin: `BvhNode` in `beam-gpu/shaders/shared/bvh.wgsl` (layouts compared by
/// `beam_gpu::interface`'s tests).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct FlatNode {
    /// Smallest corner of the box.
    pub min: [f32; 3],
    /// Right child (inner node) or first triangle reference (leaf).
    pub right_or_first: u32,
    /// Largest corner of the box.
    pub max: [f32; 3],
    /// Number of triangles; 0 for an inner node.
    pub count: u32,
}

const _: () = assert!(size_of::<FlatNode>() == 32);
const _: () = assert!(align_of::<FlatNode>() == 4);

impl FlatNode {
    /// The node's box.
    #[must_use]
    #[inline]
    pub fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::from_array(self.min), Vec3::from_array(self.max))
    }

    /// True for a leaf.
    #[must_use]
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A BVH in the compact layout, with the references and counts of its canonical tree.
#[derive(Clone, Debug, Default)]
pub struct FlatBvh {
    /// Nodes, root first, depth-first.
    pub nodes: Vec<FlatNode>,
    /// Triangle references (indices into the input slice), in leaf order.
    pub prims: Vec<u32>,
    /// Degenerate triangles left out.
    pub degenerate: usize,
    /// Number of input triangles.
    pub input_triangles: usize,
}

impl FlatBvh {
    /// Build with `options` and convert.
    #[must_use]
    pub fn build(triangles: &[Triangle], options: &BuildOptions) -> Self {
        Self::from(&build(triangles, options))
    }
}

impl From<&Bvh> for FlatBvh {
    /// Depth-first conversion; the canonical tree is already depth-first with the left child
    /// after its parent, so node indices carry over.
    fn from(bvh: &Bvh) -> Self {
        let nodes = bvh
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| match *n {
                Node::Inner { bounds, left, right } => {
                    debug_assert_eq!(left as usize, i + 1);
                    FlatNode { min: bounds.min.to_array(), right_or_first: right, max: bounds.max.to_array(), count: 0 }
                }
                Node::Leaf { bounds, first, count } => {
                    FlatNode { min: bounds.min.to_array(), right_or_first: first, max: bounds.max.to_array(), count }
                }
            })
            .collect();
        Self { nodes, prims: bvh.prims.clone(), degenerate: bvh.degenerate, input_triangles: bvh.input_triangles }
    }
}
