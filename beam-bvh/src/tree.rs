//! The canonical binary BVH: nodes with boxes and child links, leaves with ranges of triangle
//! references.

use beam_math::Aabb;
use std::vec::Vec;

/// A node of the canonical tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Node {
    /// Two children, by index into [`Bvh::nodes`].
    Inner {
        /// Bounds of both children.
        bounds: Aabb,
        /// Left child.
        left: u32,
        /// Right child.
        right: u32,
    },
    /// A range of [`Bvh::prims`].
    Leaf {
        /// Bounds of the triangles.
        bounds: Aabb,
        /// First reference.
        first: u32,
        /// Number of references.
        count: u32,
    },
}

impl Node {
    /// The node's box.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        match *self {
            Node::Inner { bounds, .. } | Node::Leaf { bounds, .. } => bounds,
        }
    }
}

/// A binary BVH over a triangle slice. Node 0 is the root; `prims` holds triangle indices into the
/// slice the tree was built from, grouped by leaf.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// Nodes, root first.
    pub nodes: Vec<Node>,
    /// Triangle references (indices into the input slice), in leaf order.
    pub prims: Vec<u32>,
    /// Triangles left out because they are degenerate (zero area, NaN or infinite coordinates).
    pub degenerate: usize,
    /// Number of input triangles.
    pub input_triangles: usize,
}
