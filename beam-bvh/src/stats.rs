//! Statistics as data: per-query counters and whole-tree figures.

use crate::flat::FlatBvh;
use beam_math::heuristics::surface_area;

/// Counters of one or more queries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    /// Nodes whose box was tested.
    pub node_visits: u64,
    /// Ray–triangle tests.
    pub triangle_tests: u64,
}

impl core::ops::AddAssign for TraversalStats {
    fn add_assign(&mut self, o: Self) {
        self.node_visits += o.node_visits;
        self.triangle_tests += o.triangle_tests;
    }
}

/// Something that counts traversal work; `()` counts nothing at no cost.
pub(crate) trait Counter {
    /// One node box tested.
    fn node(&mut self);
    /// One triangle tested.
    fn triangle(&mut self);
}

impl Counter for () {
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn triangle(&mut self) {}
}

impl Counter for TraversalStats {
    #[inline(always)]
    fn node(&mut self) {
        self.node_visits += 1;
    }
    #[inline(always)]
    fn triangle(&mut self) {
        self.triangle_tests += 1;
    }
}

/// Figures of a whole tree.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeStats {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of leaves.
    pub leaves: usize,
    /// Depth of the deepest leaf (root = 0).
    pub depth: usize,
    /// Mean triangles per leaf.
    pub mean_leaf_size: f64,
    /// Largest leaf.
    pub max_leaf_size: usize,
    /// Leaves by size: entry `k` counts leaves with `k` triangles (the last entry: that many or more).
    pub leaf_sizes: [usize; 17],
    /// SAH cost `Σ_inner A(n)/A(root) + Σ_leaf A(n)/A(root)·count` (traversal cost 1).
    pub sah_cost: f64,
    /// Degenerate triangles left out.
    pub degenerate: usize,
}

impl TreeStats {
    /// Measure `bvh`.
    #[must_use]
    pub fn of(bvh: &FlatBvh) -> Self {
        let mut s = Self {
            nodes: bvh.nodes.len(),
            leaves: 0,
            depth: 0,
            mean_leaf_size: 0.0,
            max_leaf_size: 0,
            leaf_sizes: [0; 17],
            sah_cost: 0.0,
            degenerate: bvh.degenerate,
        };
        let Some(root) = bvh.nodes.first() else {
            return s;
        };
        let root_area = f64::from(surface_area(root.bounds())).max(f64::MIN_POSITIVE);
        let mut stack = vec![(0usize, 0usize)];
        let mut total = 0usize;
        while let Some((i, depth)) = stack.pop() {
            let n = &bvh.nodes[i];
            let rel = f64::from(surface_area(n.bounds())) / root_area;
            s.depth = s.depth.max(depth);
            if n.is_leaf() {
                let c = n.count as usize;
                s.leaves += 1;
                total += c;
                s.max_leaf_size = s.max_leaf_size.max(c);
                s.leaf_sizes[c.min(16)] += 1;
                s.sah_cost += rel * c as f64;
            } else {
                s.sah_cost += rel;
                stack.push((i + 1, depth + 1));
                stack.push((n.right_or_first as usize, depth + 1));
            }
        }
        s.mean_leaf_size = total as f64 / s.leaves.max(1) as f64;
        s
    }
}
