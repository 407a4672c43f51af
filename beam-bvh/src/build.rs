//! The binary builder: binned SAH or PAH splits ([`crate::binning`]) top down, depth first with
//! the left child right after its parent, subtrees in parallel with rayon.

use crate::binning::{self, Bins, Context, Grid, PrimRef, Record};
use crate::options::BuildOptions;
use crate::tree::{Bvh, Node};
use beam_math::Triangle;
use std::vec::Vec;

/// Nodes with more references than this are built with `rayon::join` on their children. Low
/// enough that an idle thread finds work to steal when the upper splits are uneven: at 32,768 only
/// Sponza's root forked, and its two-thread 8-wide build took 7% longer (the same tree).
const PARALLEL_THRESHOLD: usize = 4096;
/// Depth after which nodes are split at the median, so trees stay below
/// `MAX_SPLIT_DEPTH + log2(n)` levels and fit [`crate::flat::STACK_SIZE`] and the GPU's
/// [`crate::gpu::GPU_STACK_SIZE`].
pub(crate) const MAX_SPLIT_DEPTH: usize = 96;

/// Build a BVH over `triangles` with `options`. Degenerate triangles (zero area, NaN or infinite
/// coordinates) are left out and counted in [`Bvh::degenerate`].
#[must_use]
pub fn build(triangles: &[Triangle], options: &BuildOptions) -> Bvh {
    let (mut refs, record) = binning::make_refs(triangles, options.parallel);
    let degenerate = triangles.len() - refs.len();
    let nodes = build_nodes(triangles, &mut refs, &record, options, Shape::FLAT);
    Bvh { nodes, prims: refs.iter().map(PrimRef::index).collect(), degenerate, input_triangles: triangles.len() }
}

/// What a binary tree is built for: its binning grid, and whether its leaves are sorted.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    pub grid: Grid,
    /// Sort each leaf's triangles by area, larger first. A tree collapsed into eight-wide nodes
    /// is sorted there, once its leaves are regrouped.
    pub sort_leaves: bool,
}

impl Shape {
    /// The binary BVH's own tree ([`build`]).
    pub(crate) const FLAT: Self = Self { grid: Grid::Centred, sort_leaves: true };
    /// A tree to be collapsed into eight-wide nodes (the direct 8-wide builder bins on its grid
    /// too).
    pub(crate) const WIDE: Self = Self { grid: Grid::Equal, sort_leaves: false };
}

/// The binary tree over `refs` (summarised by `record`), which it reorders so that each leaf's
/// references are the range it names.
pub(crate) fn build_nodes(
    triangles: &[Triangle],
    refs: &mut [PrimRef],
    record: &Record,
    options: &BuildOptions,
    shape: Shape,
) -> Vec<Node> {
    // At most 2n − 1 nodes: reserved whole, so that the vector never moves (pages not reached
    // are never touched).
    let mut nodes = Vec::with_capacity(2 * refs.len());
    if !refs.is_empty() {
        let ctx = Context::new(options, 0, shape.grid);
        let job = Job { ctx: &ctx, triangles, sort_leaves: shape.sort_leaves };
        job.node(refs, record, 0, 0, &mut nodes, &mut Box::new(Bins::EMPTY));
    }
    nodes
}

/// What every node of one build shares.
#[derive(Clone, Copy)]
struct Job<'a> {
    ctx: &'a Context,
    triangles: &'a [Triangle],
    sort_leaves: bool,
}

impl Job<'_> {
    /// Build the subtree over `refs` (summarised by `record`, starting at `offset` in the final
    /// reference order) into `nodes`; returns the node's index.
    fn node(
        self,
        refs: &mut [PrimRef],
        record: &Record,
        offset: usize,
        depth: usize,
        nodes: &mut Vec<Node>,
        scratch: &mut Bins,
    ) -> u32 {
        let ctx = self.ctx;
        let bounds = record.bounds.aabb();
        let index = nodes.len() as u32;
        let n = refs.len();
        let make_leaf = |refs: &mut [PrimRef], nodes: &mut Vec<Node>| {
            if self.sort_leaves {
                // Larger triangles first: beams split less against them (001 §3.4).
                refs.sort_unstable_by(|a, b| {
                    let area = |r: &PrimRef| self.triangles[r.index() as usize].area();
                    area(b).total_cmp(&area(a))
                });
            }
            nodes.push(Node::Leaf { bounds, first: offset as u32, count: refs.len() as u32 });
            index
        };
        if n <= 1 {
            return make_leaf(refs, nodes);
        }
        let measure = ctx.measure(bounds);
        // Past MAX_SPLIT_DEPTH, median splits bound the depth (and so the traversal stack).
        let split =
            if depth < MAX_SPLIT_DEPTH { binning::find_node_split(ctx, refs, record, measure, scratch) } else { None };
        let parent_area = measure.area4(record.bounds);
        let leaf_cost = parent_area * n as f32;
        let (mid, left_record, right_record) = match split {
            Some(s) if n > ctx.options.max_leaf || ctx.options.traversal_cost * parent_area + s.cost() < leaf_cost => {
                s.partition(refs)
            }
            // All centroids coincide, or the depth bound: split at the median if the leaf would be
            // too large.
            None if n > ctx.options.max_leaf => binning::median_split(refs, record),
            _ => return make_leaf(refs, nodes),
        };
        nodes.push(Node::Leaf { bounds, first: 0, count: 0 });
        let (left_refs, right_refs) = refs.split_at_mut(mid);
        let left;
        let right;
        if ctx.options.parallel && n > PARALLEL_THRESHOLD {
            // The left subtree goes straight into `nodes`; only the right one is built apart and
            // copied after it.
            let (l, r) = join(
                || self.node(left_refs, &left_record, offset, depth + 1, nodes, scratch),
                || {
                    let mut v = Vec::with_capacity(2 * right_refs.len());
                    let (o, d) = (offset + mid, depth + 1);
                    self.node(right_refs, &right_record, o, d, &mut v, &mut Box::new(Bins::EMPTY));
                    v
                },
            );
            left = l;
            right = append(nodes, &r, 0);
        } else {
            left = self.node(left_refs, &left_record, offset, depth + 1, nodes, scratch);
            right = self.node(right_refs, &right_record, offset + mid, depth + 1, nodes, scratch);
        }
        nodes[index as usize] = Node::Inner { bounds, left, right };
        index
    }
}

/// Append a subtree whose nodes are numbered from `first` (its root's index; 0 for one built on
/// its own) to `nodes`, renumbered; returns its root's new index.
pub(crate) fn append(nodes: &mut Vec<Node>, sub: &[Node], first: u32) -> u32 {
    let base = nodes.len() as u32;
    nodes.extend(sub.iter().map(|&n| match n {
        Node::Inner { bounds, left, right } => {
            Node::Inner { bounds, left: left - first + base, right: right - first + base }
        }
        leaf => leaf,
    }));
    base
}

#[cfg(feature = "parallel")]
pub(crate) fn join<A: Send, B: Send>(a: impl FnOnce() -> A + Send, b: impl FnOnce() -> B + Send) -> (A, B) {
    rayon::join(a, b)
}

#[cfg(not(feature = "parallel"))]
pub(crate) fn join<A, B>(a: impl FnOnce() -> A, b: impl FnOnce() -> B) -> (A, B) {
    (a(), b())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RayDistribution;
    use beam_math::glam::Vec3;

    fn grid(n: usize) -> Vec<Triangle> {
        let mut out = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let o = Vec3::new(i as f32, j as f32, 0.0);
                out.push(Triangle::new(o, o + Vec3::X, o + Vec3::Y));
                out.push(Triangle::new(o + Vec3::X, o + Vec3::ONE.with_z(0.0), o + Vec3::Y));
            }
        }
        out
    }

    #[test]
    fn every_valid_triangle_is_referenced_once() {
        let mut tris = grid(40);
        tris.push(Triangle::new(Vec3::ZERO, Vec3::X, 2.0 * Vec3::X));
        tris.push(Triangle::new(Vec3::NAN, Vec3::X, Vec3::Y));
        for options in
            [BuildOptions::sah(), BuildOptions::pah(RayDistribution::Parallel { direction: Vec3::new(0.2, 0.3, -1.0) })]
        {
            let bvh = build(&tris, &options);
            assert_eq!(bvh.degenerate, 2);
            let mut seen = bvh.prims.clone();
            seen.sort_unstable();
            assert_eq!(seen, (0..tris.len() as u32 - 2).collect::<Vec<_>>());
            // Children lie inside parents; leaves cover their triangles.
            for node in &bvh.nodes {
                match *node {
                    Node::Inner { bounds, left, right } => {
                        for c in [left, right] {
                            let cb = bvh.nodes[c as usize].bounds();
                            assert!(cb.min.cmpge(bounds.min).all() && cb.max.cmple(bounds.max).all());
                        }
                    }
                    Node::Leaf { bounds, first, count } => {
                        for &p in &bvh.prims[first as usize..(first + count) as usize] {
                            for v in tris[p as usize].v {
                                assert!(v.cmpge(bounds.min).all() && v.cmple(bounds.max).all());
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn identical_centroids_still_terminate() {
        let tris = vec![Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y); 100];
        let bvh = build(&tris, &BuildOptions { max_leaf: 4, ..BuildOptions::sah() });
        assert_eq!(bvh.prims.len(), 100);
    }
}
