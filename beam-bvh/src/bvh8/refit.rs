//! Refit of the 8-wide layout: recompute every box after the triangles moved, keeping the
//! topology.

use super::build::leaf_bounds;
use super::node::Node8;
use super::tree::Bvh8;
use beam_math::{Aabb, Triangle};

impl Bvh8 {
    /// Refresh the blocks from the moved `triangles` (same count and order as at build), then every
    /// child box bottom-up (children follow their parents, so a reverse pass suffices). Triangles
    /// left out as degenerate at build stay out.
    pub fn refit(&mut self, triangles: &[Triangle]) {
        for (k, block) in self.blocks.iter_mut().enumerate() {
            for lane in 0..4 {
                let p = self.prims[4 * k + lane];
                if p != u32::MAX {
                    block.set(lane, &triangles[p as usize]);
                }
            }
        }
        let mut node_bounds = vec![Aabb::EMPTY; self.nodes.len()];
        for i in (0..self.nodes.len()).rev() {
            let mut all = Aabb::EMPTY;
            for s in 0..8 {
                let c = self.nodes[i].child[s];
                if c == Node8::UNUSED {
                    continue;
                }
                let b = if c & Node8::LEAF != 0 {
                    leaf_bounds(&self.blocks, &self.prims, c)
                } else {
                    node_bounds[c as usize]
                };
                self.nodes[i].set_bounds(s, b);
                all = all.union(b);
            }
            node_bounds[i] = all;
        }
        self.set_tree_bounds(node_bounds.first().copied().unwrap_or(Aabb::EMPTY));
    }
}
