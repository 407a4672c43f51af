//! Optimal collapse of a binary tree into eight-wide nodes: the dynamic program of Ylitie,
//! Karras, Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs",
//! 2017, §3.1. For each binary node `n` and slot count `i ≤ 8`, `C(n, i)` is the least SAH cost
//! of representing the subtree of `n` as at most `i` roots (children of an eight-wide node):
//!
//! - `C(n, 1) = min(C_leaf(n), C_internal(n))`, with `C_leaf(n) = A(n) · ⌈P(n)/4⌉` (blocks of
//!   four triangles, as the 8-wide builder costs them; infinite beyond `max_leaf` references) and
//!   `C_internal(n) = c_t · A(n) + C_distribute(n, 8)`;
//! - `C(n, i) = min(C(n, i − 1), C_distribute(n, i))` for `i > 1`;
//! - `C_distribute(n, i) = min_{0<k<i} C(left, k) + C(right, i − k)`.
//!
//! The tree is then emitted top down by following the decisions, keeping the binary tree's
//! left-to-right order in the slots. Its cost (inner nodes `c_t · A`, leaves `A` per block) is
//! the least over all collapses whose leaves are binary subtrees, so never above
//! [`super::collapse`]'s greedy opening of the same tree.

use super::Node8;
use super::collapse::Roots;
use crate::tree::Node;
use beam_math::heuristics::surface_area;
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

/// The decisions `[n][i − 1]` of every `C(n, i)`, and for each inner node the `k` of
/// `C_distribute(n, 8)` (bottom up: children follow their parents, so a reverse pass sees
/// children first).
fn costs(tree: &[Node], max_leaf: usize, traversal_cost: f32) -> (Vec<[Choice; WIDE]>, Vec<u8>) {
    let mut internal_split = vec![0u8; tree.len()];
    let mut count = vec![0usize; tree.len()];
    let mut cost = vec![[0f32; WIDE]; tree.len()];
    let mut choice = vec![[Choice::Leaf; WIDE]; tree.len()];
    for n in (0..tree.len()).rev() {
        let area = surface_area(tree[n].bounds());
        let leaf_cost = |p: usize| if p <= max_leaf { area * p.div_ceil(4) as f32 } else { f32::INFINITY };
        match tree[n] {
            Node::Leaf { count: p, .. } => {
                debug_assert!(p as usize <= 4 * Node8::MAX_LEAF_BLOCKS);
                count[n] = p as usize;
                // A binary leaf is never split: any number of slots holds it as one leaf.
                cost[n] = [area * (p as usize).div_ceil(4) as f32; WIDE];
            }
            Node::Inner { left, right, .. } => {
                let (l, r) = (left as usize, right as usize);
                debug_assert!(l > n && r > n, "children follow their parents");
                count[n] = count[l] + count[r];
                // C_distribute(n, i) for i = 2..=8, with its best k.
                let mut dist = [(f32::INFINITY, 0u8, 0u8); WIDE];
                for i in 2..=WIDE {
                    for k in 1..i {
                        let c = cost[l][k - 1] + cost[r][i - k - 1];
                        if c < dist[i - 1].0 {
                            dist[i - 1] = (c, k as u8, (i - k) as u8);
                        }
                    }
                }
                let internal = traversal_cost * area + dist[WIDE - 1].0;
                internal_split[n] = dist[WIDE - 1].1;
                let leaf = leaf_cost(count[n]);
                let (c1, d1) = if leaf <= internal { (leaf, Choice::Leaf) } else { (internal, Choice::Internal) };
                cost[n][0] = c1;
                choice[n][0] = d1;
                for i in 2..=WIDE {
                    let (c, k, j) = dist[i - 1];
                    (cost[n][i - 1], choice[n][i - 1]) =
                        if c < cost[n][i - 2] { (c, Choice::Split(k, j)) } else { (cost[n][i - 2], choice[n][i - 2]) };
                }
            }
        }
        debug_assert!(cost[n].windows(2).all(|w| w[1] <= w[0]), "more slots never cost more");
    }
    (choice, internal_split)
}

/// The decisions of the dynamic program, followed to pick an eight-wide node's children.
pub(super) struct Optimal<'a> {
    tree: &'a [Node],
    choice: Vec<[Choice; WIDE]>,
    internal: Vec<u8>,
}

impl Roots for Optimal<'_> {
    fn is_leaf(&self, k: usize) -> bool {
        matches!(self.tree[k], Node::Leaf { .. }) || self.choice[k][0] == Choice::Leaf
    }

    fn roots(&self, i: usize, kids: &mut Vec<usize>) {
        let Node::Inner { left, right, .. } = self.tree[i] else { unreachable!("binary leaves are leaves") };
        let k = usize::from(self.internal[i]);
        debug_assert!((1..WIDE).contains(&k));
        self.split(left as usize, k, kids);
        self.split(right as usize, WIDE - k, kids);
    }
}

impl<'a> Optimal<'a> {
    /// The decisions for `tree`, subtrees of at most `max_leaf` references allowed as leaves.
    pub(super) fn new(tree: &'a [Node], max_leaf: usize, traversal_cost: f32) -> Self {
        let (choice, internal) = costs(tree, max_leaf, traversal_cost);
        Self { tree, choice, internal }
    }

    /// Push the at most `slots` roots of the subtree at `n` in the decision of `C(n, slots)`.
    fn split(&self, n: usize, slots: usize, kids: &mut Vec<usize>) {
        match self.choice[n][slots - 1] {
            Choice::Split(k, j) => {
                let Node::Inner { left, right, .. } = self.tree[n] else { unreachable!("leaves are not split") };
                self.split(left as usize, usize::from(k), kids);
                self.split(right as usize, usize::from(j), kids);
            }
            Choice::Leaf | Choice::Internal => kids.push(n),
        }
    }
}
