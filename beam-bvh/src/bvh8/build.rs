//! The 8-wide builders. By default ([`Collapse::Optimal`]) a binary SAH tree of small leaves is
//! built first, lightly reinserted (`refine.rs`, [`BuildOptions::refine`]) and collapsed into
//! eight-wide nodes by the dynamic program of `optimal.rs` (as are the reinserted and
//! spatial-split trees). With `collapse: None`, binned splits
//! ([`crate::binning`]) are taken straight into eight-wide nodes, as Embree's BVH8 builder does
//! (the rest of this note); about 20% faster to build, but its upper nodes are opened greedily,
//! and on the conference room that leaves shadow rays 7.3 triangle tests where the collapse's
//! tree needs 3.0. Each child is decided when it is made: a leaf if no split pays
//! for its node under the cost model (leaves costed in blocks of four triangles, the lanes of one
//! [`super::Tri4`] test) and it is small enough, else a node-to-be with its split already found.
//! A node starts with its references as one child and keeps splitting its child of largest
//! surface area that is not a leaf, until it has eight children or only leaves; with slots left it
//! then splits the leaves whose cut lowers their cost (no node is added). Each split is searched
//! once. Subtrees over many references build in parallel.
//!
//! (Opening every child of more than one block regardless of cost gives fuller nodes and smaller
//! leaves but no faster queries with these kernels: measured on Sponza and the conference room.)

use super::node::Node8;
use super::tree::Bvh8;
use super::tri4::Tri4;
use crate::binning::{self, Bins, Context, PrimRef, Record, Split};
use crate::build::{MAX_SPLIT_DEPTH, Shape};
use crate::options::{BuildOptions, Collapse, Heuristic};
use beam_math::heuristics::surface_area;
use beam_math::{Aabb, Triangle};
use std::vec::Vec;

/// Children of more references than this build in parallel.
const PARALLEL_THRESHOLD: usize = 4096;
/// Most triangles in a leaf.
const MAX_LEAF: usize = 4 * Node8::MAX_LEAF_BLOCKS;
/// Children of at most this many triangles (one block) are not split further.
const MIN_LEAF: usize = 4;

/// How a child is split when it is opened.
#[derive(Clone, Copy, Debug)]
enum Cut {
    /// At most one block: never split.
    None,
    Binned(Split),
    /// Binning cannot separate the centroids, or the depth bound: split at the median.
    Median,
}

/// A child-to-be: its references `begin..end` of the node's, their record, its depth in binary
/// splits, how it is split, and whether it becomes a leaf when reached.
#[derive(Clone, Copy, Debug)]
struct Child {
    begin: usize,
    end: usize,
    record: Record,
    depth: usize,
    cut: Cut,
    leaf: bool,
    /// How much its binned cut lowers its cost as a leaf (area times blocks); 0 without one.
    gain: f32,
}

/// Build over `triangles`.
pub(super) fn build(triangles: &[Triangle], options: &BuildOptions) -> Bvh8 {
    let (mut refs, mut record) = binning::make_refs(triangles, options.parallel);
    let mut out =
        Bvh8 { degenerate: triangles.len() - refs.len(), input_triangles: triangles.len(), ..Bvh8::default() };
    if refs.is_empty() {
        return out;
    }
    let presplit = options.presplit > 0.0;
    let spatial = options.spatial > 0.0;
    if presplit {
        refs = super::presplit::presplit(refs, triangles, options.presplit, record.bounds.aabb());
        record = binning::record_of(&refs, options.parallel);
    }
    let mut options = *options;
    options.max_leaf = options.max_leaf.clamp(1, MAX_LEAF);
    if (options.reinsert || options.collapse.is_some() || spatial) && options.heuristic == Heuristic::Sah {
        // A binary tree of small leaves (with spatial splits, or of whole triangles), optimized,
        // then collapsed: the collapse regroups leaves.
        let binary = BuildOptions { max_leaf: options.max_leaf.min(MIN_LEAF), ..options };
        let (tree, refs) = if spatial {
            super::spatial::build(triangles, refs, record, &binary)
        } else {
            (crate::build::build_nodes(triangles, &mut refs, &record, &binary, Shape::WIDE), refs)
        };
        let tree = if options.reinsert {
            crate::reinsert::optimize(&tree, options.traversal_cost)
        } else {
            crate::refine::refine(&tree, options.refine).unwrap_or(tree)
        };
        let kind = options.collapse.unwrap_or(Collapse::Greedy);
        let (nodes, order) = super::collapse::collapse(&tree, &refs, kind, &options);
        let mut order = order.unwrap_or(refs);
        out.set_tree_bounds(record.bounds.aabb());
        let dedupe = presplit || spatial;
        finish(&mut out, nodes, &mut order, triangles, FinishOptions { parallel: options.parallel, dedupe });
        return out;
    }
    let ctx = Context::new(&options, 2, Shape::WIDE.grid);
    let mut scratch = Box::new(Bins::EMPTY);
    let root = prepare(&ctx, &refs, 0, refs.len(), record, 0, &mut scratch);
    let mut nodes = Vec::with_capacity(refs.len() / 4 + 1);
    node(&ctx, &mut refs, 0, root, &mut nodes, &mut scratch);
    out.set_tree_bounds(record.bounds.aabb());
    finish(&mut out, nodes, &mut refs, triangles, FinishOptions { parallel: options.parallel, dedupe: presplit });
    out
}

/// The child over `refs[begin..end]`: its split, and whether the cost model makes it a leaf (no
/// split pays for its node, and it is at most `max_leaf` references).
fn prepare(
    ctx: &Context,
    refs: &[PrimRef],
    begin: usize,
    end: usize,
    record: Record,
    depth: usize,
    scratch: &mut Bins,
) -> Child {
    let child = Child { begin, end, record, depth, cut: Cut::None, leaf: true, gain: 0.0 };
    let n = end - begin;
    if n <= MIN_LEAF {
        return child;
    }
    let bounds = record.bounds.aabb();
    let measure = ctx.measure(bounds);
    let split = if depth < MAX_SPLIT_DEPTH {
        binning::find_split(ctx, &refs[begin..end], &record, measure, scratch)
    } else {
        None
    };
    let area = measure.area4(record.bounds);
    let leaf = n <= ctx.options.max_leaf
        && split.is_none_or(|s| ctx.options.traversal_cost * area + s.cost >= area * ctx.blocks(n));
    let gain = split.map_or(0.0, |s| area * ctx.blocks(n) - s.cost);
    Child { cut: split.map_or(Cut::Median, Cut::Binned), leaf, gain, ..child }
}

/// Build the node of `me` (not a leaf) over `refs` (its references, at `offset` in the final
/// order) into `nodes`; returns its index. Leaf slots hold their first reference and `tris` their
/// count until [`finish`] makes the blocks.
fn node(
    ctx: &Context,
    refs: &mut [PrimRef],
    offset: usize,
    me: Child,
    nodes: &mut Vec<Node8>,
    scratch: &mut Bins,
) -> u32 {
    let index = nodes.len();
    nodes.push(Node8::EMPTY);
    let mut kids = [me; 8];
    kids[0] = Child { begin: 0, end: refs.len(), ..me };
    let mut count = 1;
    if me.leaf {
        // Only the root of a tiny tree: one leaf child.
        debug_assert!(index == 0);
    } else {
        while count < 8 {
            let open = (0..count).filter(|&i| !kids[i].leaf).max_by(|&a, &b| area(&kids[a]).total_cmp(&area(&kids[b])));
            // Every child a leaf and slots left: split the leaf whose cut lowers its cost most (no
            // node is added, so the traversal cost does not count).
            let open = open.or_else(|| {
                let gain = |i: usize| if kids[i].leaf { kids[i].gain } else { 0.0 };
                (0..count).filter(|&i| gain(i) > 0.0).max_by(|&a, &b| gain(a).total_cmp(&gain(b)))
            });
            let Some(i) = open else { break };
            let (left, right) = split(ctx, refs, &kids[i], scratch);
            kids[i] = left;
            kids[count] = right;
            count += 1;
        }
    }
    let kids = &mut kids[..count];
    kids.sort_unstable_by_key(|k| k.begin);
    // Each inner child's subtree, built here or on another thread, as nodes with local indices.
    let mut parts: Vec<(&mut [PrimRef], Child)> = Vec::with_capacity(count);
    let mut rest = refs;
    for k in kids.iter() {
        let (head, tail) = rest.split_at_mut(k.end - k.begin);
        parts.push((head, *k));
        rest = tail;
    }
    debug_assert!(rest.is_empty());
    let big = kids.iter().filter(|k| k.end - k.begin > PARALLEL_THRESHOLD).count();
    if ctx.options.parallel && big > 1 {
        let subtrees = par_map(parts, |(slice, k)| {
            (!k.leaf).then(|| {
                let mut v = Vec::new();
                let me = Child { begin: 0, end: k.end - k.begin, ..k };
                node(ctx, slice, offset + k.begin, me, &mut v, &mut Box::new(Bins::EMPTY));
                v
            })
        });
        for (slot, (k, sub)) in kids.iter().zip(subtrees).enumerate() {
            let child = sub.map(|sub| append(nodes, sub));
            set_slot(&mut nodes[index], slot, offset, k, child);
        }
    } else {
        for (slot, (slice, k)) in parts.into_iter().enumerate() {
            let child = (!k.leaf).then(|| {
                let me = Child { begin: 0, end: k.end - k.begin, ..k };
                node(ctx, slice, offset + k.begin, me, nodes, scratch)
            });
            set_slot(&mut nodes[index], slot, offset, &k, child);
        }
    }
    index as u32
}

/// Fill slot `slot` of `n` with child `k`: inner node `child`, or (for `None`) a leaf given by its
/// first reference and count until [`finish`].
fn set_slot(n: &mut Node8, slot: usize, offset: usize, k: &Child, child: Option<u32>) {
    n.set_bounds(slot, k.record.bounds.aabb());
    match child {
        Some(c) => n.child[slot] = c,
        None => {
            n.child[slot] = (offset + k.begin) as u32;
            n.tris[slot] = (k.end - k.begin) as u8;
        }
    }
}

fn area(k: &Child) -> f32 {
    surface_area(k.record.bounds.aabb())
}

/// Split `k` by its cut into two prepared children.
fn split(ctx: &Context, refs: &mut [PrimRef], k: &Child, scratch: &mut Bins) -> (Child, Child) {
    let slice = &mut refs[k.begin..k.end];
    let (mid, l, r) = match k.cut {
        Cut::Binned(s) => binning::partition(slice, &s),
        Cut::Median => binning::median_split(slice, &k.record),
        Cut::None => unreachable!("children of one block are not split"),
    };
    debug_assert!(mid > 0 && mid < slice.len());
    let (d, m) = (k.depth + 1, k.begin + mid);
    (prepare(ctx, refs, k.begin, m, l, d, scratch), prepare(ctx, refs, m, k.end, r, d, scratch))
}

/// Append a subtree built with local indices; returns its root's new index.
fn append(nodes: &mut Vec<Node8>, sub: Vec<Node8>) -> u32 {
    let base = nodes.len() as u32;
    nodes.extend(sub.into_iter().map(|mut n| {
        for s in 0..8 {
            if n.tris[s] == 0 && n.child[s] != Node8::UNUSED {
                n.child[s] += base;
            }
        }
        n
    }));
    base
}

/// `f` of each item, every item a task of its own (the few large children of a node).
#[cfg(feature = "parallel")]
fn par_map<T: Send, R: Send>(items: Vec<T>, f: impl Fn(T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    items.into_par_iter().with_max_len(1).map(f).collect()
}

/// `f` on every item, in parallel tasks of at least 256 items.
#[cfg(feature = "parallel")]
fn par_for_each<T: Send>(items: Vec<T>, f: impl Fn(T) + Sync + Send) {
    use rayon::prelude::*;
    items.into_par_iter().with_min_len(256).for_each(f);
}

#[cfg(not(feature = "parallel"))]
fn par_for_each<T>(items: Vec<T>, f: impl Fn(T)) {
    items.into_iter().for_each(f);
}

/// `len` copies of `value`, written by all threads (with `parallel`: the leaf blocks of a large
/// tree are megabytes).
#[cfg(feature = "parallel")]
fn filled<T: Clone + Send + Sync>(len: usize, value: T, parallel: bool) -> Vec<T> {
    use rayon::prelude::*;
    if !parallel || len < PARALLEL_THRESHOLD {
        return vec![value; len];
    }
    let mut v = Vec::with_capacity(len);
    v.par_extend(rayon::iter::repeat_n(value, len).with_min_len(PARALLEL_THRESHOLD));
    v
}

#[cfg(not(feature = "parallel"))]
fn filled<T: Clone>(len: usize, value: T, _parallel: bool) -> Vec<T> {
    vec![value; len]
}

#[cfg(not(feature = "parallel"))]
fn par_map<T, R>(items: Vec<T>, f: impl Fn(T) -> R) -> Vec<R> {
    items.into_iter().map(f).collect()
}

/// Copy each leaf's triangles into blocks of four (in node order, so a node's leaves lie
/// together), replace leaf slots by block references, and measure the stack a traversal needs.
/// How [`finish`] runs.
struct FinishOptions {
    parallel: bool,
    /// Leaves may hold pieces of one triangle more than once (pre-splitting): keep one.
    dedupe: bool,
}

fn finish(out: &mut Bvh8, nodes: Vec<Node8>, refs: &mut [PrimRef], triangles: &[Triangle], opt: FinishOptions) {
    let mut nodes = super::layout::group_siblings(nodes, opt.parallel);
    if opt.dedupe {
        for n in &mut nodes {
            for s in 0..8 {
                let (first, count) = (n.child[s] as usize, n.tris[s] as usize);
                if count > 1 {
                    n.tris[s] = dedupe(&mut refs[first..first + count]) as u8;
                }
            }
        }
    }
    let refs = &*refs;
    let parallel = opt.parallel;
    // Each node's leaves take consecutive blocks, from a prefix sum of the nodes' block counts;
    // then every node fills its own blocks (in parallel for large trees).
    let mut first_block = Vec::with_capacity(nodes.len() + 1);
    let mut total = 0usize;
    for n in &nodes {
        first_block.push(total);
        total += n.tris.iter().map(|&c| (c as usize).div_ceil(4)).sum::<usize>();
    }
    first_block.push(total);
    let mut blocks = filled(total, Tri4::EMPTY, parallel);
    let mut prims = filled(4 * total, u32::MAX, parallel);
    let mut work = Vec::with_capacity(nodes.len());
    let (mut rest_b, mut rest_p) = (&mut blocks[..], &mut prims[..]);
    for (i, n) in nodes.iter_mut().enumerate() {
        let k = first_block[i + 1] - first_block[i];
        let (b, tail_b) = rest_b.split_at_mut(k);
        let (p, tail_p) = rest_p.split_at_mut(4 * k);
        work.push((n, first_block[i], b, p));
        (rest_b, rest_p) = (tail_b, tail_p);
    }
    let fill = |(n, start, b, p): (&mut Node8, usize, &mut [Tri4], &mut [u32])| {
        let mut next = 0;
        for s in 0..8 {
            let count = n.tris[s] as usize;
            if count == 0 {
                continue;
            }
            let first = n.child[s] as usize;
            n.child[s] = Node8::leaf_ref((start + next) as u32, count.div_ceil(4) as u32);
            // Larger triangles in the first blocks: an any-hit query meets them sooner. Each area
            // is computed once (as a sort key it was 5% of a build), as `|n|²` (it orders as the
            // area does, without a square root). Squares are not negative: their bits order as
            // they do.
            let mut keyed = [(0u32, 0u32); MAX_LEAF];
            let keyed = &mut keyed[..count];
            for (k, r) in keyed.iter_mut().zip(&refs[first..first + count]) {
                *k = (triangles[r.index() as usize].scaled_normal().length_squared().to_bits(), r.index());
            }
            keyed.sort_unstable_by_key(|k| core::cmp::Reverse(k.0));
            for (j, &(_, i)) in keyed.iter().enumerate() {
                b[next + j / 4].set(j % 4, &triangles[i as usize]);
                p[4 * next + j] = i;
            }
            next += count.div_ceil(4);
        }
    };
    if parallel && refs.len() > PARALLEL_THRESHOLD {
        par_for_each(work, fill);
    } else {
        work.into_iter().for_each(fill);
    }
    // Children follow their parents, so one reverse pass sees every child's need first.
    let mut need = vec![0usize; nodes.len()];
    for i in (0..nodes.len()).rev() {
        let n = &nodes[i];
        let used = n.child.iter().filter(|&&c| c != Node8::UNUSED).count();
        let below =
            (0..8).filter(|&s| n.tris[s] == 0 && n.child[s] != Node8::UNUSED).map(|s| need[n.child[s] as usize]);
        need[i] = used.saturating_sub(1) + below.max().unwrap_or(0);
    }
    out.stack_need = need.first().copied().unwrap_or(0);
    out.nodes = nodes;
    out.blocks = blocks;
    out.prims = prims;
}

/// Move one reference of each triangle of `leaf` to its front; returns how many.
fn dedupe(leaf: &mut [PrimRef]) -> usize {
    leaf.sort_unstable_by_key(PrimRef::index);
    let mut unique = 1;
    for i in 1..leaf.len() {
        if leaf[i].index() != leaf[unique - 1].index() {
            leaf[unique] = leaf[i];
            unique += 1;
        }
    }
    unique
}

/// Box of a leaf's triangles.
pub(super) fn leaf_bounds(blocks: &[Tri4], prims: &[u32], r: u32) -> Aabb {
    let (first, count) = Node8::leaf_blocks(r);
    let mut b = Aabb::EMPTY;
    for k in first..first + count {
        for lane in 0..4 {
            if prims[4 * k + lane] != u32::MAX {
                b = blocks[k].triangle(lane).v.iter().fold(b, |b, &v| b.grow(v));
            }
        }
    }
    b
}
