//! Collapse of a binary tree into eight-wide nodes: the default 8-wide build's second half, and
//! that of trees optimized as binary trees first ([`crate::reinsert`], spatial splits). The
//! greedy collapse: one bottom-up pass decides which subtrees become leaves, the cheaper of a
//! leaf, `A · ⌈n/4⌉` (blocks of four triangles), and the children's optimal costs plus `c_t · A`
//! with `c_t` [`NODE_COST`] times the build's traversal cost (the leaf half of the dynamic program
//! of Ylitie, Karras, Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide
//! BVHs", 2017, §3.1); then, top down, each eight-wide node opens its child of largest surface
//! area that is not a leaf until it has eight children, keeping the binary tree's left-to-right
//! order in its slots. The optimal collapse (`optimal.rs`) picks leaves and children by the whole
//! dynamic program instead; both are emitted here.

use super::node::Node8;
use super::optimal::Optimal;
use super::roots::{NODE_COST, Roots, cost_area};
use crate::binning::PrimRef;
use crate::options::{BuildOptions, Collapse};
use crate::tree::Node;
use std::vec::Vec;

/// The eight-wide nodes of `tree` (root first, children after their parents; its leaves index
/// `refs`) and the references in their new leaf order, collapsed the `kind` way: `None` where that
/// is the order of `refs` (leaves met left to right in `refs`' order, as the binary builder lays
/// them out). Leaf slots hold their first reference and `tris` their count, as the 8-wide builder
/// leaves them for `finish`. Subtrees of at most `options.max_leaf` references may become leaves.
pub(super) fn collapse(
    tree: &[Node],
    refs: &[PrimRef],
    kind: Collapse,
    options: &BuildOptions,
) -> (Vec<Node8>, Option<Vec<PrimRef>>) {
    let max_leaf = options.max_leaf;
    let node_cost = NODE_COST * options.traversal_cost;
    match kind {
        Collapse::Greedy => emit(tree, refs, &Greedy { tree, leaf: leaves(tree, max_leaf, node_cost) }),
        Collapse::Optimal => emit(tree, refs, &Optimal::new(tree, max_leaf, node_cost)),
    }
}

/// For each node of `tree`, whether its subtree becomes one leaf (bottom up: children follow
/// their parents, so a reverse pass sees children first). Only subtrees of at most `max_leaf`
/// references may, whatever the costs.
fn leaves(tree: &[Node], max_leaf: usize, node_cost: f32) -> Vec<bool> {
    let node_cost = f64::from(node_cost);
    let mut count = vec![0usize; tree.len()];
    let mut cost = vec![0f64; tree.len()];
    let mut leaf = vec![false; tree.len()];
    for i in (0..tree.len()).rev() {
        let area = cost_area(tree[i].bounds());
        let blocks = |n: usize| n.div_ceil(4) as f64;
        match tree[i] {
            Node::Leaf { count: c, .. } => {
                debug_assert!(c as usize <= 4 * Node8::MAX_LEAF_BLOCKS);
                count[i] = c as usize;
                cost[i] = area * blocks(c as usize);
                leaf[i] = true;
            }
            Node::Inner { left, right, .. } => {
                let (l, r) = (left as usize, right as usize);
                debug_assert!(l > i && r > i, "children follow their parents");
                count[i] = count[l] + count[r];
                let inner = node_cost * area + cost[l] + cost[r];
                let as_leaf = area * blocks(count[i]);
                leaf[i] = count[i] <= max_leaf && as_leaf <= inner;
                cost[i] = if leaf[i] { as_leaf } else { inner };
            }
        }
    }
    leaf
}

/// The greedy choice of an eight-wide node's children: open the child of largest surface area
/// that is not a leaf until there are eight.
struct Greedy<'a> {
    tree: &'a [Node],
    leaf: Vec<bool>,
}

impl Roots for Greedy<'_> {
    fn is_leaf(&self, k: usize) -> bool {
        self.leaf[k]
    }

    fn roots(&self, i: usize, kids: &mut Vec<usize>) {
        let area = |k: usize| cost_area(self.tree[k].bounds());
        kids.push(i);
        while kids.len() < 8 {
            let open = (0..kids.len())
                .filter(|&k| !self.leaf[kids[k]])
                .max_by(|&a, &b| area(kids[a]).total_cmp(&area(kids[b])));
            let Some(k) = open else { break };
            let Node::Inner { left, right, .. } = self.tree[kids[k]] else { unreachable!("leaves are not opened") };
            kids.splice(k..=k, [left as usize, right as usize]);
        }
    }
}

/// The eight-wide nodes of `tree` with children picked by `picks` (root first, children after
/// their parents) and the references in their new leaf order (`None`: that of `refs`). Leaf
/// slots hold their first reference and `tris` their count, as the 8-wide builder leaves them for
/// `finish`.
fn emit(tree: &[Node], refs: &[PrimRef], picks: &impl Roots) -> (Vec<Node8>, Option<Vec<PrimRef>>) {
    let mut out = Emit {
        tree,
        refs,
        picks,
        nodes: Vec::with_capacity(tree.len() / 4 + 1),
        placed: 0,
        order: None,
        scratch: Vec::with_capacity(8),
    };
    if !tree.is_empty() {
        out.node(0);
    }
    debug_assert_eq!(out.placed, refs.len(), "every reference lands in one leaf");
    (out.nodes, out.order)
}

/// The emission in progress.
struct Emit<'a, R> {
    tree: &'a [Node],
    refs: &'a [PrimRef],
    picks: &'a R,
    nodes: Vec<Node8>,
    /// How many references the leaves emitted so far hold.
    placed: usize,
    /// The references in leaf order, copied only from the first leaf met out of `refs`' order:
    /// until then the first `placed` references of `refs` are the order.
    order: Option<Vec<PrimRef>>,
    /// Where [`Roots::roots`] writes a node's children (copied out before the recursion).
    scratch: Vec<usize>,
}

impl<R: Roots> Emit<'_, R> {
    /// Make the eight-wide node of binary node `i`; returns its index.
    fn node(&mut self, i: usize) -> u32 {
        let index = self.nodes.len();
        self.nodes.push(Node8::EMPTY);
        self.scratch.clear();
        if self.picks.is_leaf(i) {
            // Only the root of a tiny tree: one leaf child.
            debug_assert!(index == 0);
            self.scratch.push(i);
        } else {
            self.picks.roots(i, &mut self.scratch);
            debug_assert!((2..=8).contains(&self.scratch.len()));
        }
        let mut kids = [0usize; 8];
        kids[..self.scratch.len()].copy_from_slice(&self.scratch);
        for (slot, &k) in kids[..self.scratch.len()].iter().enumerate() {
            self.nodes[index].set_bounds(slot, self.tree[k].bounds());
            if self.picks.is_leaf(k) {
                let first = self.placed;
                self.gather(k);
                let n = self.placed - first;
                debug_assert!((1..=4 * Node8::MAX_LEAF_BLOCKS).contains(&n));
                self.nodes[index].child[slot] = first as u32;
                self.nodes[index].tris[slot] = n as u8;
            } else {
                let child = self.node(k);
                self.nodes[index].child[slot] = child;
            }
        }
        index as u32
    }

    /// Append the references of the subtree at `i` to the new order.
    fn gather(&mut self, i: usize) {
        match self.tree[i] {
            Node::Leaf { first, count, .. } => {
                let leaf = &self.refs[first as usize..(first + count) as usize];
                match &mut self.order {
                    None if first as usize == self.placed => {}
                    None => {
                        let mut order = Vec::with_capacity(self.refs.len());
                        order.extend_from_slice(&self.refs[..self.placed]);
                        order.extend_from_slice(leaf);
                        self.order = Some(order);
                    }
                    Some(order) => order.extend_from_slice(leaf),
                }
                self.placed += count as usize;
            }
            Node::Inner { left, right, .. } => {
                self.gather(left as usize);
                self.gather(right as usize);
            }
        }
    }
}
