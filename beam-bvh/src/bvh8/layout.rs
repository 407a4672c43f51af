//! The order of a finished tree's nodes: every node's inner children in its first slots and at
//! consecutive indices ([`Node8::base`], [`Node8::inner`]), sibling groups laid out depth first
//! from the root, so children still follow their parents. With it the x86 kernels compute the
//! index of the next node from the slot they picked instead of loading it, which takes a load off
//! the chain of dependent operations a traversal step is.

use super::node::Node8;
use std::vec::Vec;

/// `nodes` (root first, children after their parents) renumbered so that every node's inner
/// children take consecutive indices, with each node's slots ordered inner children, leaves,
/// unused. Runs before leaves become block references: a leaf slot is one with `tris > 0` (every
/// leaf has a triangle), an inner child one with `tris == 0`.
pub(super) fn group_siblings(mut nodes: Vec<Node8>, parallel: bool) -> Vec<Node8> {
    if nodes.is_empty() {
        return nodes;
    }
    for_each(&mut nodes, parallel, order_slots);
    // `order[new] = old`; a node's inner children are appended together when it is reached.
    let mut order = Vec::with_capacity(nodes.len());
    let mut new_index = std::vec![u32::MAX; nodes.len()];
    order.push(0usize);
    new_index[0] = 0;
    let mut pending = std::vec![0usize];
    while let Some(old) = pending.pop() {
        let n = &nodes[old];
        let first = order.len();
        for s in 0..n.inner as usize {
            let c = n.child[s] as usize;
            new_index[c] = order.len() as u32;
            order.push(c);
        }
        // The first child's group next, so a subtree's groups lie together.
        pending.extend(order[first..].iter().rev());
    }
    debug_assert_eq!(order.len(), nodes.len(), "every node is reached from the root once");
    let renumbered = |old: &usize| {
        let mut n = nodes[*old];
        for s in 0..n.inner as usize {
            n.child[s] = new_index[n.child[s] as usize];
        }
        n.base = if n.inner > 0 { n.child[0] } else { 0 };
        debug_assert!((0..n.inner as usize).all(|s| n.child[s] == n.base + s as u32));
        n
    };
    #[cfg(feature = "parallel")]
    if parallel && nodes.len() > PARALLEL_NODES {
        use rayon::prelude::*;
        return order.par_iter().with_min_len(256).map(renumbered).collect();
    }
    let _ = parallel;
    order.iter().map(renumbered).collect()
}

/// Trees of more nodes than this are laid out by all threads.
#[cfg(feature = "parallel")]
const PARALLEL_NODES: usize = 4096;

/// `f` on every node, by all threads for large trees (with `parallel`).
fn for_each(nodes: &mut [Node8], parallel: bool, f: fn(&mut Node8)) {
    #[cfg(feature = "parallel")]
    if parallel && nodes.len() > PARALLEL_NODES {
        use rayon::prelude::*;
        nodes.par_iter_mut().with_min_len(256).for_each(f);
        return;
    }
    let _ = parallel;
    nodes.iter_mut().for_each(f);
}

/// Reorder the slots of `n`: inner children (in their order), then leaves, then unused slots;
/// set [`Node8::inner`].
fn order_slots(n: &mut Node8) {
    let kinds: [u8; 8] = core::array::from_fn(|s| match (n.child[s], n.tris[s]) {
        (Node8::UNUSED, _) => 2,
        (_, 0) => 0,
        _ => 1,
    });
    let mut slots: [usize; 8] = core::array::from_fn(|s| s);
    slots.sort_by_key(|&s| kinds[s]);
    let old = *n;
    for (to, &from) in slots.iter().enumerate() {
        n.child[to] = old.child[from];
        n.tris[to] = old.tris[from];
        for k in 0..6 {
            n.bounds[k][to] = old.bounds[k][from];
        }
    }
    n.inner = kinds.iter().filter(|&&k| k == 0).count() as u8;
}
