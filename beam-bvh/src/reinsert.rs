//! Tree optimization by reinsertion (Bittner, Hapala, Havran, "Fast Insertion-Based Optimization
//! of Bounding Volume Hierarchies", 2013): a top-down builder decides each split once, with what
//! it sees of one node; afterwards, nodes whose box is large for what they hold (the paper's
//! inefficiency `M = A(N) · A(N)/min(A(L), A(R)) · A(N)/mean(A(L), A(R))`, its `M_sum·M_min·M_area`)
//! are taken out of the tree with their parent and inserted back where they raise the SAH cost
//! least (one subtree at a time, as in Meister and Bittner, "Parallel Reinsertion for Bounding
//! Volume Hierarchy Optimization", 2018, so that the old place is among the choices and no step
//! raises the cost), found by a branch-and-bound search from the root (§4.2:
//! the cost of putting `X` beside `Y` is `A(X ∪ Y)` plus what it adds to the boxes of `Y`'s
//! ancestors). Passes repeat while the SAH cost keeps falling; the best tree seen is returned, so
//! the cost never rises.
//!
//! Leaves and their references are moved, never changed: each leaf keeps its range.

use crate::tree::Node;
use beam_math::Aabb;
use beam_math::heuristics::surface_area;
use std::collections::BinaryHeap;
use std::vec::Vec;

pub(crate) const NONE: u32 = u32::MAX;

/// Most passes.
const MAX_PASSES: usize = 8;
/// Nodes with a smaller surface area than this fraction of the root's stay where they are: on
/// Sponza, moving them costs two thirds of the time and gains nothing in queries.
const MIN_AREA: f32 = 1e-4;
/// Stop after this many passes in a row that each lower the cost by less than [`MIN_GAIN`].
const PATIENCE: usize = 1;
/// Relative cost decrease below which a pass counts as no gain.
const MIN_GAIN: f64 = 0.002;

/// A node with its parent link; a leaf (no children, `kids[0] == NONE`) holds references
/// `first..first + count` (in [`crate::refine`]: a block, the subtree of `count` nodes whose root
/// is node `first` of the binary tree).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Link {
    pub bounds: Aabb,
    pub area: f32,
    pub parent: u32,
    pub kids: [u32; 2],
    pub first: u32,
    pub count: u32,
}

/// The tree being optimized.
#[derive(Clone)]
pub(crate) struct Tree {
    pub n: Vec<Link>,
    pub root: u32,
    pub min_area: f32,
}

/// `nodes` (root first, as the binary builder makes them) after reinsertion passes, root first
/// and each left child right after its parent. `traversal_cost` is the SAH cost of an inner node
/// relative to one reference of a leaf.
#[must_use]
pub(crate) fn optimize(nodes: &[Node], traversal_cost: f32) -> Vec<Node> {
    if nodes.len() < 8 {
        return nodes.to_vec();
    }
    let mut tree = Tree::new(nodes);
    let mut best = tree.clone();
    let mut best_cost = tree.cost(traversal_cost);
    let mut stalled = 0;
    for _ in 0..MAX_PASSES {
        tree.pass(usize::MAX);
        let cost = tree.cost(traversal_cost);
        if cost < best_cost * (1.0 - MIN_GAIN) {
            stalled = 0;
        } else {
            stalled += 1;
        }
        if cost < best_cost {
            best_cost = cost;
            best.clone_from(&tree);
        }
        if stalled >= PATIENCE {
            break;
        }
    }
    best.check();
    best.to_nodes(nodes.len(), |l, out| out.push(Node::Leaf { bounds: l.bounds, first: l.first, count: l.count }))
}

/// The SAH cost of `nodes` relative to its root's box: `Σ_inner c_t·A + Σ_leaf count·A`, over
/// `A(root)`.
#[must_use]
#[cfg(test)]
pub(crate) fn sah_cost(nodes: &[Node], traversal_cost: f32) -> f64 {
    if nodes.is_empty() {
        return 0.0;
    }
    Tree::new(nodes).cost(traversal_cost)
}

/// A search entry: a node and the cost its ancestors' boxes would gain (min-heap on that cost).
#[derive(Clone, Copy, PartialEq)]
struct Entry {
    induced: f32,
    node: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> core::cmp::Ordering {
        o.induced.total_cmp(&self.induced)
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<core::cmp::Ordering> {
        Some(self.cmp(o))
    }
}

impl Tree {
    fn new(nodes: &[Node]) -> Self {
        let mut n: Vec<Link> = nodes
            .iter()
            .map(|node| {
                let bounds = node.bounds();
                let (kids, first, count) = match *node {
                    Node::Inner { left, right, .. } => ([left, right], 0, 0),
                    Node::Leaf { first, count, .. } => ([NONE; 2], first, count),
                };
                Link { bounds, area: surface_area(bounds), parent: NONE, kids, first, count }
            })
            .collect();
        for i in 0..n.len() {
            for k in n[i].kids {
                if k != NONE {
                    n[k as usize].parent = i as u32;
                }
            }
        }
        let min_area = n[0].area * MIN_AREA;
        Self { n, root: 0, min_area }
    }

    fn is_leaf(&self, i: u32) -> bool {
        self.n[i as usize].kids[0] == NONE
    }

    fn cost(&self, traversal_cost: f32) -> f64 {
        let total: f64 = self
            .n
            .iter()
            .map(|l| {
                if l.kids[0] == NONE {
                    f64::from(l.area) * f64::from(l.count)
                } else {
                    f64::from(traversal_cost * l.area)
                }
            })
            .sum();
        total / f64::from(self.n[self.root as usize].area).max(f64::MIN_POSITIVE)
    }

    /// One pass: take out each node of at least `min_area` (the `limit` most inefficient of
    /// them), in order of decreasing inefficiency (leaves by their area), with its parent, and
    /// insert it back where the SAH cost is least. That place may be where it was, so no step
    /// raises the cost.
    pub(crate) fn pass(&mut self, limit: usize) {
        let mut candidates: Vec<(f32, u32)> = (0..self.n.len() as u32)
            .filter(|&i| i != self.root && self.n[i as usize].area >= self.min_area)
            .map(|i| (if self.is_leaf(i) { self.n[i as usize].area } else { self.inefficiency(i) }, i))
            .collect();
        let by_inefficiency = |a: &(f32, u32), b: &(f32, u32)| b.0.total_cmp(&a.0);
        if limit < candidates.len() {
            candidates.select_nth_unstable_by(limit, by_inefficiency);
            candidates.truncate(limit);
        }
        candidates.sort_unstable_by(by_inefficiency);
        let mut heap = BinaryHeap::new();
        for &(_, x) in &candidates {
            if x == self.root {
                continue;
            }
            let freed = self.remove(x);
            let y = self.find_best(x, &mut heap);
            self.insert(x, y, freed);
        }
    }

    /// Bittner's `M_sum · M_min · M_area` of inner node `i`.
    fn inefficiency(&self, i: u32) -> f32 {
        let l = &self.n[i as usize];
        let (a, b) = (self.n[l.kids[0] as usize].area, self.n[l.kids[1] as usize].area);
        let m_min = l.area / a.min(b).max(f32::MIN_POSITIVE);
        let m_sum = l.area / (0.5 * (a + b)).max(f32::MIN_POSITIVE);
        l.area * m_min * m_sum
    }

    /// Take `x` (not the root) and its parent out of the tree (the sibling takes the parent's
    /// place); returns the parent's slot, now free. `x` stays detached.
    fn remove(&mut self, x: u32) -> u32 {
        let p = self.n[x as usize].parent;
        debug_assert!(p != NONE);
        let g = self.n[p as usize].parent;
        let pk = self.n[p as usize].kids;
        let sibling = if pk[0] == x { pk[1] } else { pk[0] };
        if g == NONE {
            self.root = sibling;
            self.n[sibling as usize].parent = NONE;
        } else {
            self.replace_child(g, p, sibling);
            self.refit(g);
        }
        self.n[x as usize].parent = NONE;
        p
    }

    /// In `g`'s children, replace `old` by `new`.
    fn replace_child(&mut self, g: u32, old: u32, new: u32) {
        let gk = &mut self.n[g as usize].kids;
        let slot = usize::from(gk[1] == old);
        debug_assert_eq!(gk[slot], old);
        gk[slot] = new;
        self.n[new as usize].parent = g;
    }

    /// Recompute boxes from `i` up to the root, stopping where a box does not change.
    fn refit(&mut self, mut i: u32) {
        while i != NONE {
            let [a, b] = self.n[i as usize].kids;
            let bounds = self.n[a as usize].bounds.union(self.n[b as usize].bounds);
            let link = &mut self.n[i as usize];
            if bounds == link.bounds {
                break;
            }
            link.bounds = bounds;
            link.area = surface_area(bounds);
            i = link.parent;
        }
    }

    /// The node beside which detached subtree `x` raises the SAH cost least (branch and bound).
    fn find_best(&self, x: u32, heap: &mut BinaryHeap<Entry>) -> u32 {
        let xb = self.n[x as usize].bounds;
        let xa = self.n[x as usize].area;
        heap.clear();
        heap.push(Entry { induced: 0.0, node: self.root });
        let (mut best, mut best_cost) = (self.root, f32::INFINITY);
        while let Some(Entry { induced, node }) = heap.pop() {
            if induced + xa >= best_cost {
                break;
            }
            let l = &self.n[node as usize];
            let direct = surface_area(l.bounds.union(xb));
            if induced + direct < best_cost {
                best_cost = induced + direct;
                best = node;
            }
            let below = induced + direct - l.area;
            if l.kids[0] != NONE && below + xa < best_cost {
                for k in l.kids {
                    heap.push(Entry { induced: below, node: k });
                }
            }
        }
        best
    }

    /// Put detached `x` beside `y`, under the free slot `q`.
    fn insert(&mut self, x: u32, y: u32, q: u32) {
        let p = self.n[y as usize].parent;
        if p == NONE {
            self.root = q;
            self.n[q as usize].parent = NONE;
        } else {
            self.replace_child(p, y, q);
        }
        let bounds = self.n[x as usize].bounds.union(self.n[y as usize].bounds);
        let link = &mut self.n[q as usize];
        *link = Link { bounds, area: surface_area(bounds), kids: [y, x], first: 0, count: 0, ..*link };
        self.n[x as usize].parent = q;
        self.n[y as usize].parent = q;
        self.refit(p);
    }

    /// Debug checks: every node is reached once from the root, and every box holds its
    /// children's.
    pub(crate) fn check(&self) {
        if !cfg!(debug_assertions) {
            return;
        }
        let mut seen = vec![false; self.n.len()];
        let mut stack = vec![self.root];
        while let Some(i) = stack.pop() {
            debug_assert!(!seen[i as usize], "node {i} reached twice");
            seen[i as usize] = true;
            let l = &self.n[i as usize];
            if l.kids[0] != NONE {
                for k in l.kids {
                    let kb = self.n[k as usize].bounds;
                    let inside = kb.min.cmpge(l.bounds.min).all() && kb.max.cmple(l.bounds.max).all();
                    debug_assert!(inside, "node {i} does not enclose child {k}");
                    debug_assert_eq!(self.n[k as usize].parent, i);
                    stack.push(k);
                }
            }
        }
        debug_assert!(seen.iter().all(|&s| s), "a node left the tree");
    }

    /// The tree as `len` builder nodes: root first, each left child right after its parent;
    /// `leaf` appends what stands for a leaf (one node, or a whole subtree in the same order).
    pub(crate) fn to_nodes(&self, len: usize, mut leaf: impl FnMut(&Link, &mut Vec<Node>)) -> Vec<Node> {
        let mut out = Vec::with_capacity(len);
        let mut stack = vec![(self.root, NONE, 0usize)];
        while let Some((i, parent, side)) = stack.pop() {
            let index = out.len() as u32;
            let l = &self.n[i as usize];
            if parent != NONE {
                if let Node::Inner { left, right, .. } = &mut out[parent as usize] {
                    *(if side == 0 { left } else { right }) = index;
                }
            }
            if l.kids[0] == NONE {
                leaf(l, &mut out);
            } else {
                out.push(Node::Inner { bounds: l.bounds, left: NONE, right: NONE });
                stack.push((l.kids[1], index, 1));
                stack.push((l.kids[0], index, 0));
            }
        }
        out
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::binning;
    use crate::options::BuildOptions;
    use crate::traverse::tests::soup;
    use beam_math::Triangle;

    /// Every reference lies in exactly one leaf, every box holds its children (leaves: their
    /// triangles), and children follow their parents.
    pub(crate) fn check_tree(nodes: &[Node], prims: &[u32], tris: &[Triangle]) {
        let mut seen = vec![0u32; prims.len()];
        for (i, node) in nodes.iter().enumerate() {
            match *node {
                Node::Inner { bounds, left, right } => {
                    for c in [left, right] {
                        assert!(c as usize > i, "child {c} before parent {i}");
                        let cb = nodes[c as usize].bounds();
                        assert!(cb.min.cmpge(bounds.min).all() && cb.max.cmple(bounds.max).all());
                    }
                }
                Node::Leaf { bounds, first, count } => {
                    for r in first..first + count {
                        seen[r as usize] += 1;
                        for v in tris[prims[r as usize] as usize].v {
                            assert!(v.cmpge(bounds.min).all() && v.cmple(bounds.max).all());
                        }
                    }
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1), "a reference in no leaf or in two");
    }

    #[test]
    fn reinsertion_keeps_the_references_and_lowers_the_cost() {
        for (n, seed, max_leaf) in [(3000, 5, 1), (5000, 11, 4), (40, 2, 4)] {
            let tris = soup(n, seed);
            let (mut refs, record) = binning::make_refs(&tris, false);
            let options = BuildOptions { max_leaf, parallel: false, ..BuildOptions::sah() };
            let nodes = crate::build::build_nodes(&tris, &mut refs, &record, &options, crate::build::Shape::FLAT);
            let prims: Vec<u32> = refs.iter().map(|r| r.index()).collect();
            let optimized = optimize(&nodes, 1.0);
            assert_eq!(optimized.len(), nodes.len());
            assert_eq!(optimized[0].bounds(), nodes[0].bounds());
            check_tree(&optimized, &prims, &tris);
            let (before, after) = (sah_cost(&nodes, 1.0), sah_cost(&optimized, 1.0));
            assert!(after <= before, "{n}: SAH cost rose from {before} to {after}");
            if n >= 1000 {
                assert!(after < 0.99 * before, "{n}: SAH cost barely fell: {before} → {after}");
            }
        }
    }
}
