//! The light reinsertion of the 8-wide builder ([`crate::BuildOptions::refine`]): one pass of
//! [`crate::reinsert`] over the few most inefficient nodes of the binary tree's upper part, the
//! rest of the tree moved as whole subtrees.
//!
//! A top-down builder's worst mistakes are few and high in the tree (Bittner et al. 2013 §5: the
//! nodes of largest inefficiency `M = A(N) · A(N)/min(A(L), A(R)) · A(N)/mean(A(L), A(R))`).
//! Reinserting only the 0.3% most inefficient nodes, once, removes 7–10% of the box tests of
//! Sponza's and the conference room's rays, much of what the full optimization
//! ([`crate::BuildOptions::reinsert`]) gains, at a small part of its time: the pass works on the
//! nodes of at least [`UPPER_AREA`] of the root's area (a sixth of them on Sponza), every
//! smaller subtree a fixed block that is copied back whole. Its cost is that copy: 0.6 ms of
//! Sponza's 17 ms build, 2.5 ms of the conference room's 85 (the pass itself 0.25 and 0.8).

use crate::build::append;
use crate::reinsert::{Link, NONE, Tree};
use crate::tree::Node;
use beam_math::heuristics::surface_area;
use std::vec::Vec;

/// Nodes of less than this fraction of the root's surface area stay inside their blocks: with
/// 3·10⁻⁴ the refined trees of Sponza and the conference room are those of 10⁻⁴ (the full
/// optimization's bound), with 10⁻³ the conference room's keeps 7% more box tests.
const UPPER_AREA: f32 = 3e-4;

/// `nodes` (root first, each subtree in pre-order: a node, its left subtree, its right subtree,
/// as the binary builders make them) after reinserting its `fraction` most inefficient nodes;
/// `None` when there is nothing to do.
#[must_use]
pub(crate) fn refine(nodes: &[Node], fraction: f32) -> Option<Vec<Node>> {
    let limit = (fraction * nodes.len() as f32).ceil() as usize;
    if nodes.len() < 8 || limit == 0 {
        return None;
    }
    let mut tree = upper_tree(nodes);
    tree.pass(limit);
    tree.check();
    let out = tree.to_nodes(nodes.len(), |l, out| {
        // A block: the subtree of `count` nodes at `first`, its child links moved with it.
        let from = l.first as usize;
        append(out, &nodes[from..from + l.count as usize], l.first);
    });
    debug_assert_eq!(out.len(), nodes.len());
    Some(out)
}

/// The nodes of at least [`UPPER_AREA`] of the root's area as a [`Tree`], and below them the
/// smaller subtrees as blocks: leaves whose `first` is the subtree's root's index in `nodes` and
/// `count` its number of nodes (in pre-order, a left child's subtree ends where its sibling's
/// begins, and a right child's where its parent's ends).
fn upper_tree(nodes: &[Node]) -> Tree {
    let min_area = surface_area(nodes[0].bounds()) * UPPER_AREA;
    let mut n: Vec<Link> = Vec::new();
    // (index in `nodes`, end of its subtree, parent in `n`, side)
    let mut stack = std::vec![(0u32, nodes.len() as u32, NONE, 0usize)];
    while let Some((i, end, parent, side)) = stack.pop() {
        let k = n.len() as u32;
        let bounds = nodes[i as usize].bounds();
        let area = surface_area(bounds);
        n.push(Link { bounds, area, parent, kids: [NONE; 2], first: i, count: end - i });
        if parent != NONE {
            n[parent as usize].kids[side] = k;
        }
        if let Node::Inner { left, right, .. } = nodes[i as usize] {
            debug_assert!(left == i + 1 && left < right && right < end, "not in pre-order");
            if area >= min_area {
                stack.push((right, end, k, 1));
                stack.push((left, right, k, 0));
            }
        }
    }
    Tree { n, root: 0, min_area }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binning;
    use crate::options::BuildOptions;
    use crate::reinsert::{sah_cost, tests::check_tree};
    use crate::traverse::tests::soup;

    /// The refined tree keeps every reference in one leaf and every box around its children, is
    /// in pre-order again, costs less, and moves only subtrees: the same leaves.
    #[test]
    fn refinement_keeps_the_references_and_lowers_the_cost() {
        for (n, seed, fraction) in [(6000, 3, 0.003), (6000, 3, 0.05), (40, 2, 0.5)] {
            let tris = soup(n, seed);
            let (mut refs, record) = binning::make_refs(&tris, false);
            let options = BuildOptions { max_leaf: 4, parallel: false, ..BuildOptions::sah() };
            let nodes = crate::build::build_nodes(&tris, &mut refs, &record, &options, crate::build::Shape::WIDE);
            let prims: Vec<u32> = refs.iter().map(|r| r.index()).collect();
            let refined = refine(&nodes, fraction).expect("a tree in pre-order");
            assert_eq!(refined.len(), nodes.len());
            check_tree(&refined, &prims, &tris);
            assert!(in_pre_order(&refined), "{n}, {fraction}: not in pre-order");
            let leaves = |t: &[Node]| {
                let mut v: Vec<Node> = t.iter().filter(|n| matches!(n, Node::Leaf { .. })).copied().collect();
                v.sort_by_key(|n| match n {
                    Node::Leaf { first, .. } => *first,
                    Node::Inner { .. } => unreachable!(),
                });
                v
            };
            assert_eq!(leaves(&refined), leaves(&nodes), "leaves are moved, never changed");
            let (before, after) = (sah_cost(&nodes, 1.0), sah_cost(&refined, 1.0));
            assert!(after <= before, "{n}: SAH cost rose from {before} to {after}");
            // A random soup's binned tree is close to its best: any move at all lowers the cost.
            assert!(n < 1000 || after < before, "{n}, {fraction}: SAH cost did not fall: {before}");
        }
        assert!(refine(&[], 0.5).is_none() && refine(&soup_tree(), 0.0).is_none());
    }

    /// Whether every node is followed by its left subtree, then its right one.
    fn in_pre_order(nodes: &[Node]) -> bool {
        fn end(nodes: &[Node], i: usize) -> Option<usize> {
            match nodes[i] {
                Node::Leaf { .. } => Some(i + 1),
                Node::Inner { left, right, .. } => {
                    let l = end(nodes, i + 1).filter(|_| left as usize == i + 1)?;
                    end(nodes, l).filter(|_| right as usize == l)
                }
            }
        }
        end(nodes, 0) == Some(nodes.len())
    }

    fn soup_tree() -> Vec<Node> {
        let tris = soup(100, 1);
        let (mut refs, record) = binning::make_refs(&tris, false);
        let options = BuildOptions { parallel: false, ..BuildOptions::sah() };
        crate::build::build_nodes(&tris, &mut refs, &record, &options, crate::build::Shape::WIDE)
    }
}
