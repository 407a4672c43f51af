//! Optimal collapse of a binary tree into eight-wide nodes: the dynamic program of Ylitie,
//! Karras, Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs",
//! 2017, §3.1. For each binary node `n` and slot count `i ≤ 8`, `C(n, i)` is the least SAH cost
//! of representing the subtree of `n` as at most `i` roots (children of an eight-wide node):
//!
//! - `C(n, 1) = min(C_leaf(n), C_internal(n))`, with `C_leaf(n) = A(n) · ⌈P(n)/4⌉` (blocks of
//!   four triangles, as the 8-wide builder costs them; no leaf beyond `max_leaf` references) and
//!   `C_internal(n) = c_t · A(n) + C_distribute(n, 8)` (`c_t`: [`super::roots::NODE_COST`]
//!   times the build's traversal cost);
//! - `C(n, i) = min(C(n, i − 1), C_distribute(n, i))` for `i > 1`;
//! - `C_distribute(n, i) = min_{0<k<i} C(left, k) + C(right, i − k)`.
//!
//! The tree is then emitted top down by following the decisions, keeping the binary tree's
//! left-to-right order in the slots. Its cost (inner nodes `c_t · A`, leaves `A` per block) is
//! the least over all collapses whose leaves are binary subtrees. Trees laid out depth first (as
//! the binary builder makes them) are solved a subtree per task. Costs are `f64` areas
//! ([`super::roots::cost_area`]): finite for every finite box. (With `f32` areas a mesh with
//! one vertex at 10³⁰ made every cost infinite, and `C_leaf = ∞ ≤ C_internal = ∞` chose a leaf
//! of 65 triangles, past the limit, as the leaf limit was an infinite cost; the limit is a
//! condition now.)

use super::node::Node8;
use super::roots::{Roots, cost_area};
use crate::tree::Node;
use std::vec::Vec;

/// Slots of an eight-wide node.
const WIDE: usize = 8;

/// The decision of `C(n, i)`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Choice {
    /// One root: `n` itself, a leaf.
    Leaf,
    /// One root: `n` itself, an eight-wide node distributing its children over eight slots.
    Internal,
    /// The left child's subtree in at most `k` roots, the right's in at most `j` (`k + j ≤ i`).
    Split(u8, u8),
}

impl Choice {
    /// One byte: 0, 255, or `k` and `j` (each below 8) as two nibbles.
    fn encode(self) -> u8 {
        match self {
            Choice::Leaf => 0,
            Choice::Internal => 0xff,
            Choice::Split(k, j) => k << 4 | j,
        }
    }

    fn decode(b: u8) -> Self {
        match b {
            0 => Choice::Leaf,
            0xff => Choice::Internal,
            b => Choice::Split(b >> 4, b & 0xf),
        }
    }
}

/// The decisions at one binary node: of `C(n, 1..=8)` ([`Choice::encode`]d), and the `k` of
/// `C_distribute(n, 8)` (inner nodes).
#[derive(Clone, Copy, Debug, Default)]
struct Decisions {
    choice: [u8; WIDE],
    internal: u8,
}

/// What a node's parent needs of its solution: `C(n, 1..=8)`, the references below, and the
/// fewest slots from which more cost no less (`C(n, i) = C(n, 8)` for `i ≥ flat`).
#[derive(Clone, Copy, Debug)]
struct Costs {
    cost: [f64; WIDE],
    count: usize,
    flat: usize,
}

/// Subtrees of more binary nodes than this solve their two children in parallel.
const PARALLEL_NODES: usize = 8192;

/// The solution at binary node `n` from its children's (`None` for a leaf).
fn solve(node: &Node, children: Option<(Costs, Costs)>, max_leaf: usize, node_cost: f32) -> (Costs, Decisions) {
    let area = cost_area(node.bounds());
    let Some((l, r)) = children else {
        let Node::Leaf { count: p, .. } = *node else { unreachable!("inner nodes have children") };
        debug_assert!(p as usize <= 4 * Node8::MAX_LEAF_BLOCKS);
        // A binary leaf is never split: any number of slots holds it as one leaf.
        let cost = [area * (p as usize).div_ceil(4) as f64; WIDE];
        return (Costs { cost, count: p as usize, flat: 1 }, Decisions::default());
    };
    let count = l.count + r.count;
    // C_distribute(n, i) for i = 2..=8, with its best k (the first of equal costs). Beyond
    // `l.flat` a larger k gives the left no less and the right no more slots: never cheaper.
    let mut dist = [(f64::INFINITY, 0u8, 0u8); WIDE];
    for i in 2..=WIDE {
        for k in 1..i.min(l.flat + 1) {
            let c = l.cost[k - 1] + r.cost[i - k - 1];
            // The first k whatever its cost: a split is always a valid choice.
            if k == 1 || c < dist[i - 1].0 {
                dist[i - 1] = (c, k as u8, (i - k) as u8);
            }
        }
    }
    let internal = f64::from(node_cost) * area + dist[WIDE - 1].0;
    // A leaf only within the limit: a condition, not a cost (an infinite cost ties with others).
    let leaf = (count <= max_leaf).then(|| area * count.div_ceil(4) as f64);
    let mut cost = [0.0; WIDE];
    let mut choice = [Choice::Leaf; WIDE];
    (cost[0], choice[0]) = match leaf {
        Some(leaf) if leaf <= internal => (leaf, Choice::Leaf),
        _ => (internal, Choice::Internal),
    };
    for i in 2..=WIDE {
        let (c, k, j) = dist[i - 1];
        (cost[i - 1], choice[i - 1]) =
            if c < cost[i - 2] { (c, Choice::Split(k, j)) } else { (cost[i - 2], choice[i - 2]) };
    }
    debug_assert!(cost.windows(2).all(|w| w[1] <= w[0]), "more slots never cost more");
    let flat = (1..=WIDE).find(|&i| cost[i - 1] == cost[WIDE - 1]).unwrap_or(WIDE);
    (Costs { cost, count, flat }, Decisions { choice: choice.map(Choice::encode), internal: dist[WIDE - 1].1 })
}

/// The decisions at every node of `tree`.
fn solve_all(tree: &[Node], max_leaf: usize, node_cost: f32) -> Vec<Decisions> {
    let mut out = vec![Decisions::default(); tree.len()];
    if solve_subtree(tree, 0, &mut out, max_leaf, node_cost).is_some() {
        return out;
    }
    // Not laid out depth first: children follow their parents, so a reverse pass sees children
    // first.
    let mut costs = vec![Costs { cost: [0.0; WIDE], count: 0, flat: 1 }; tree.len()];
    for n in (0..tree.len()).rev() {
        let children = match tree[n] {
            Node::Inner { left, right, .. } => {
                debug_assert!(left as usize > n && right as usize > n, "children follow their parents");
                Some((costs[left as usize], costs[right as usize]))
            }
            Node::Leaf { .. } => None,
        };
        (costs[n], out[n]) = solve(&tree[n], children, max_leaf, node_cost);
    }
    out
}

/// Solve the subtree rooted at `n` if it is laid out depth first in `out` (its slice of the
/// decisions, as the binary builder lays trees out: `n`, its left subtree, its right subtree);
/// returns its costs, or `None` where the layout is another.
fn solve_subtree(tree: &[Node], n: usize, out: &mut [Decisions], max_leaf: usize, node_cost: f32) -> Option<Costs> {
    let (me, below) = out.split_first_mut()?;
    let children = match tree[n] {
        Node::Leaf { .. } if below.is_empty() => None,
        Node::Inner { left, right, .. } if left as usize == n + 1 && right > left => {
            let (l, r) = (left as usize, right as usize);
            let parallel = below.len() > PARALLEL_NODES;
            let (left_out, right_out) = below.split_at_mut_checked(r - l)?;
            let (a, b) = if parallel {
                crate::build::join(
                    || solve_subtree(tree, l, left_out, max_leaf, node_cost),
                    || solve_subtree(tree, r, right_out, max_leaf, node_cost),
                )
            } else {
                (
                    solve_subtree(tree, l, left_out, max_leaf, node_cost),
                    solve_subtree(tree, r, right_out, max_leaf, node_cost),
                )
            };
            Some((a?, b?))
        }
        _ => return None,
    };
    let (costs, decisions) = solve(&tree[n], children, max_leaf, node_cost);
    *me = decisions;
    Some(costs)
}

/// The decisions of the dynamic program, followed to pick an eight-wide node's children.
pub(super) struct Optimal<'a> {
    tree: &'a [Node],
    decisions: Vec<Decisions>,
}

impl Roots for Optimal<'_> {
    fn is_leaf(&self, k: usize) -> bool {
        matches!(self.tree[k], Node::Leaf { .. }) || Choice::decode(self.decisions[k].choice[0]) == Choice::Leaf
    }

    fn roots(&self, i: usize, kids: &mut Vec<usize>) {
        let Node::Inner { left, right, .. } = self.tree[i] else { unreachable!("binary leaves are leaves") };
        let k = usize::from(self.decisions[i].internal);
        debug_assert!((1..WIDE).contains(&k));
        self.split(left as usize, k, kids);
        self.split(right as usize, WIDE - k, kids);
    }
}

impl<'a> Optimal<'a> {
    /// The decisions for `tree`, subtrees of at most `max_leaf` references allowed as leaves.
    pub(super) fn new(tree: &'a [Node], max_leaf: usize, node_cost: f32) -> Self {
        Self { tree, decisions: solve_all(tree, max_leaf, node_cost) }
    }

    /// Push the at most `slots` roots of the subtree at `n` in the decision of `C(n, slots)`.
    fn split(&self, n: usize, slots: usize, kids: &mut Vec<usize>) {
        match Choice::decode(self.decisions[n].choice[slots - 1]) {
            Choice::Split(k, j) => {
                let Node::Inner { left, right, .. } = self.tree[n] else { unreachable!("leaves are not split") };
                self.split(left as usize, usize::from(k), kids);
                self.split(right as usize, usize::from(j), kids);
            }
            Choice::Leaf | Choice::Internal => kids.push(n),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BuildOptions;
    use crate::binning::make_refs;
    use crate::build::{Shape, build_nodes};
    use crate::traverse::tests::soup;

    /// The binary builder's tree in breadth-first order: children still follow their parents,
    /// but no longer depth first.
    fn breadth_first(tree: &[Node]) -> (Vec<Node>, Vec<usize>) {
        let mut order = vec![0usize];
        let mut i = 0;
        while i < order.len() {
            if let Node::Inner { left, right, .. } = tree[order[i]] {
                order.extend([left as usize, right as usize]);
            }
            i += 1;
        }
        let mut new_index = vec![0u32; tree.len()];
        for (to, &from) in order.iter().enumerate() {
            new_index[from] = to as u32;
        }
        let nodes = order
            .iter()
            .map(|&n| match tree[n] {
                Node::Inner { bounds, left, right } => {
                    Node::Inner { bounds, left: new_index[left as usize], right: new_index[right as usize] }
                }
                leaf => leaf,
            })
            .collect();
        (nodes, order)
    }

    /// The subtree-per-task solution of a depth-first tree equals the reverse pass's over the same
    /// tree in another order, node for node.
    #[test]
    fn both_passes_decide_alike() {
        let tris = soup(20_000, 9);
        let (mut refs, record) = make_refs(&tris, false);
        let options = BuildOptions { max_leaf: 4, parallel: false, ..BuildOptions::sah() };
        let tree = build_nodes(&tris, &mut refs, &record, &options, Shape::WIDE);
        let (shuffled, order) = breadth_first(&tree);
        assert!(tree.len() > 2 * PARALLEL_NODES, "large enough to solve in parallel");
        let (a, b) = (solve_all(&tree, 8, 1.5), solve_all(&shuffled, 8, 1.5));
        for (to, &from) in order.iter().enumerate() {
            assert_eq!((a[from].choice, a[from].internal), (b[to].choice, b[to].internal), "node {from}");
        }
    }
}
