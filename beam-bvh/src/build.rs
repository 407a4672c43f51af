//! The binned builder (Wald 2007 style binning) with a pluggable area measure: surface area (SAH)
//! or projected area (PAH, 004), plus the partition directions of splitting-plane facing.

use crate::options::{BuildOptions, Heuristic, RayDistribution};
use crate::tree::{Bvh, Node};
use beam_math::glam::Vec3;
use beam_math::heuristics::{projected_area_orthographic_fast, projected_area_perspective_fast, surface_area};
use beam_math::{Aabb, Triangle};
use std::vec::Vec;

/// A triangle reference during the build.
#[derive(Clone, Copy, Debug)]
struct PrimRef {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
    area: f32,
}

/// Nodes with more references than this are built with `rayon::join` on their children.
const PARALLEL_THRESHOLD: usize = 8192;
/// Depth after which nodes are split at the median, so trees stay below
/// `MAX_SPLIT_DEPTH + log2(n)` levels and fit [`crate::flat::STACK_SIZE`] and the GPU's
/// [`crate::gpu::GPU_STACK_SIZE`].
pub(crate) const MAX_SPLIT_DEPTH: usize = 96;
/// Largest number of bins.
const MAX_BINS: usize = 32;

/// Build a BVH over `triangles` with `options`. Degenerate triangles (zero area, NaN or infinite
/// coordinates) are left out and counted in [`Bvh::degenerate`].
#[must_use]
pub fn build(triangles: &[Triangle], options: &BuildOptions) -> Bvh {
    let mut refs: Vec<PrimRef> = triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| t.is_valid())
        .map(|(i, t)| {
            let bounds = Aabb::from_points(&t.v);
            PrimRef { bounds, centroid: bounds.center(), index: i as u32, area: t.area() }
        })
        .collect();
    let degenerate = triangles.len() - refs.len();
    let mut nodes = Vec::with_capacity(2 * refs.len() / options.max_leaf.max(1) + 1);
    if !refs.is_empty() {
        let ctx = Context::new(options);
        build_node(&ctx, &mut refs, 0, 0, &mut nodes, &mut Box::new(Bins::EMPTY));
    }
    Bvh { nodes, prims: refs.iter().map(|r| r.index).collect(), degenerate, input_triangles: triangles.len() }
}

/// Per-build constants.
struct Context {
    options: BuildOptions,
    directions: [Vec3; 5],
    direction_count: usize,
}

impl Context {
    fn new(options: &BuildOptions) -> Self {
        let mut directions = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ZERO, Vec3::ZERO];
        let mut direction_count = 3;
        if let Some(d) = options.facing.and_then(Vec3::try_normalize) {
            let u = d.any_orthonormal_vector();
            directions[3] = u;
            directions[4] = d.cross(u);
            direction_count = 5;
        }
        let mut options = *options;
        options.bins = options.bins.clamp(2, MAX_BINS);
        options.max_leaf = options.max_leaf.max(1);
        Self { options, directions, direction_count }
    }

    /// The area measure for the children of a node with box `parent`: projected area when the
    /// distribution applies to the whole node, surface area otherwise (004's fallback).
    fn measure(&self, parent: Aabb) -> Measure {
        match self.options.heuristic {
            Heuristic::Sah => Measure::Surface,
            Heuristic::Pah(RayDistribution::Parallel { direction }) => Measure::Orthographic(direction),
            Heuristic::Pah(RayDistribution::Pencil { origin, forward }) => {
                if projected_area_perspective_fast(parent, origin, forward).is_some() {
                    Measure::Perspective(origin, forward)
                } else {
                    Measure::Surface
                }
            }
        }
    }
}

#[derive(Clone, Copy)]
enum Measure {
    Surface,
    Orthographic(Vec3),
    Perspective(Vec3, Vec3),
}

impl Measure {
    fn area(self, b: Aabb) -> f32 {
        if !b.is_valid() {
            return 0.0;
        }
        match self {
            Measure::Surface => surface_area(b),
            Measure::Orthographic(d) => projected_area_orthographic_fast(b, d),
            Measure::Perspective(o, f) => projected_area_perspective_fast(b, o, f).unwrap_or(f32::INFINITY),
        }
    }
}

/// The best partition of a node: along `direction`, references with bin `< bin` go left.
#[derive(Clone, Copy)]
struct Split {
    direction: Vec3,
    lo: f32,
    scale: f32,
    bin: usize,
    cost: f32,
}

fn bin_of(r: &PrimRef, s: &Split, bins: usize) -> usize {
    (((r.centroid.dot(s.direction) - s.lo) * s.scale) as usize).min(bins - 1)
}

/// Bin contents for every partition direction.
#[derive(Clone, Copy)]
struct Bins {
    bounds: [[Aabb; MAX_BINS]; 5],
    counts: [[u32; MAX_BINS]; 5],
}

impl Bins {
    const EMPTY: Self = Self { bounds: [[Aabb::EMPTY; MAX_BINS]; 5], counts: [[0; MAX_BINS]; 5] };

    fn merge(mut self, o: Self) -> Self {
        for d in 0..5 {
            for b in 0..MAX_BINS {
                self.bounds[d][b] = self.bounds[d][b].union(o.bounds[d][b]);
                self.counts[d][b] += o.counts[d][b];
            }
        }
        self
    }
}

/// Nodes with more references than this bin in parallel chunks.
const PARALLEL_BINNING: usize = 32_768;

/// `f` over chunks of `refs` merged with `merge`, in parallel for large slices.
fn reduce_chunks<T: Send + Sync + Copy>(
    refs: &[PrimRef],
    parallel: bool,
    init: T,
    f: impl Fn(&[PrimRef]) -> T + Sync + Send,
    merge: impl Fn(T, T) -> T + Sync + Send,
) -> T {
    #[cfg(feature = "parallel")]
    if parallel && refs.len() > PARALLEL_BINNING {
        use rayon::prelude::*;
        return refs.par_chunks(PARALLEL_BINNING / 4).map(&f).reduce(|| init, &merge);
    }
    let _ = (parallel, &merge, init);
    f(refs)
}

/// Find the cheapest binned split (cost `A(L)·N_L + A(R)·N_R` under `measure`), binning every
/// partition direction in one pass over the references.
fn find_split(ctx: &Context, refs: &[PrimRef], measure: Measure, scratch: &mut Bins) -> Option<Split> {
    // Small nodes need few bins; fewer bins also means less to clear and sweep.
    let bins = ctx.options.bins.min(refs.len().max(4));
    let dirs = &ctx.directions[..ctx.direction_count];
    let parallel = ctx.options.parallel;
    let ranges = reduce_chunks(
        refs,
        parallel,
        [(f32::INFINITY, f32::NEG_INFINITY); 5],
        |chunk| {
            let mut r = [(f32::INFINITY, f32::NEG_INFINITY); 5];
            for p in chunk {
                for (d, dir) in dirs.iter().enumerate() {
                    let x = p.centroid.dot(*dir);
                    r[d] = (r[d].0.min(x), r[d].1.max(x));
                }
            }
            r
        },
        |a, b| core::array::from_fn(|d| (a[d].0.min(b[d].0), a[d].1.max(b[d].1))),
    );
    let probes: [Option<Split>; 5] = core::array::from_fn(|d| {
        let (lo, hi) = ranges[d];
        (d < dirs.len() && hi - lo > 1e-20 * (lo.abs() + hi.abs()).max(1e-30)).then(|| Split {
            direction: dirs[d],
            lo,
            scale: bins as f32 / (hi - lo) * (1.0 - 1e-6),
            bin: 0,
            cost: 0.0,
        })
    });
    // Clear the bins in use, then add every reference of `chunk` to its bin in each direction.
    let bin_chunk = |chunk: &[PrimRef], out: &mut Bins| {
        for d in 0..dirs.len() {
            out.bounds[d][..bins].fill(Aabb::EMPTY);
            out.counts[d][..bins].fill(0);
        }
        for p in chunk {
            for (d, probe) in probes.iter().enumerate() {
                if let Some(probe) = probe {
                    let b = bin_of(p, probe, bins);
                    out.bounds[d][b] = out.bounds[d][b].union(p.bounds);
                    out.counts[d][b] += 1;
                }
            }
        }
    };
    if parallel && refs.len() > PARALLEL_BINNING {
        let chunk = |c: &[PrimRef]| {
            let mut out = Bins::EMPTY;
            bin_chunk(c, &mut out);
            out
        };
        *scratch = reduce_chunks(refs, parallel, Bins::EMPTY, chunk, Bins::merge);
    } else {
        bin_chunk(refs, scratch);
    }
    let binned = &*scratch;
    let mut best: Option<Split> = None;
    for (d, probe) in probes.iter().enumerate() {
        let Some(probe) = probe else { continue };
        let (bounds, counts) = (&binned.bounds[d], &binned.counts[d]);
        // Sweep from the right, then from the left.
        let mut right_area = [0.0f32; MAX_BINS];
        let mut acc = Aabb::EMPTY;
        let mut n = 0u32;
        for b in (1..bins).rev() {
            acc = acc.union(bounds[b]);
            n += counts[b];
            right_area[b] = measure.area(acc) * n as f32;
        }
        let mut acc = Aabb::EMPTY;
        let mut n = 0u32;
        for b in 1..bins {
            acc = acc.union(bounds[b - 1]);
            n += counts[b - 1];
            if n == 0 || n as usize == refs.len() {
                continue;
            }
            let cost = measure.area(acc) * n as f32 + right_area[b];
            if best.as_ref().is_none_or(|s| cost < s.cost) {
                best = Some(Split { bin: b, cost, ..*probe });
            }
        }
    }
    best
}

/// In-place partition; returns the number of references on the left.
fn partition(refs: &mut [PrimRef], left: impl Fn(&PrimRef) -> bool) -> usize {
    let mut i = 0;
    for j in 0..refs.len() {
        if left(&refs[j]) {
            refs.swap(i, j);
            i += 1;
        }
    }
    i
}

/// Build the subtree over `refs` (which start at `offset` in the final reference order) into
/// `nodes`, depth first with the left child right after its parent; returns the node's index.
fn build_node(
    ctx: &Context,
    refs: &mut [PrimRef],
    offset: usize,
    depth: usize,
    nodes: &mut Vec<Node>,
    scratch: &mut Bins,
) -> u32 {
    let bounds = refs.iter().fold(Aabb::EMPTY, |b, r| b.union(r.bounds));
    let index = nodes.len() as u32;
    let n = refs.len();
    let make_leaf = |refs: &mut [PrimRef], nodes: &mut Vec<Node>| {
        // Larger triangles first: beams split less against them (001 §3.4).
        refs.sort_unstable_by(|a, b| b.area.total_cmp(&a.area));
        nodes.push(Node::Leaf { bounds, first: offset as u32, count: refs.len() as u32 });
        index
    };
    if n <= 1 {
        return make_leaf(refs, nodes);
    }
    let measure = ctx.measure(bounds);
    // Past MAX_SPLIT_DEPTH, median splits bound the depth (and so the traversal stack).
    let split = if depth < MAX_SPLIT_DEPTH { find_split(ctx, refs, measure, scratch) } else { None };
    let parent_area = measure.area(bounds);
    let leaf_cost = parent_area * n as f32;
    let mid = match split {
        Some(s) if n > ctx.options.max_leaf || ctx.options.traversal_cost * parent_area + s.cost < leaf_cost => {
            let bins = ctx.options.bins;
            partition(refs, |r| bin_of(r, &s, bins) < s.bin)
        }
        // All centroids coincide: split by count if the leaf would be too large.
        None if n > ctx.options.max_leaf => {
            if depth >= MAX_SPLIT_DEPTH {
                let axis = bounds.extent().max_position();
                refs.sort_unstable_by(|a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
            }
            n / 2
        }
        _ => return make_leaf(refs, nodes),
    };
    nodes.push(Node::Leaf { bounds, first: 0, count: 0 });
    let (left_refs, right_refs) = refs.split_at_mut(mid);
    let left;
    let right;
    if ctx.options.parallel && n > PARALLEL_THRESHOLD {
        let (l, r) = join(
            || {
                let mut v = Vec::new();
                build_node(ctx, left_refs, offset, depth + 1, &mut v, &mut Box::new(Bins::EMPTY));
                v
            },
            || {
                let mut v = Vec::new();
                build_node(ctx, right_refs, offset + mid, depth + 1, &mut v, &mut Box::new(Bins::EMPTY));
                v
            },
        );
        left = append(nodes, l);
        right = append(nodes, r);
    } else {
        left = build_node(ctx, left_refs, offset, depth + 1, nodes, scratch);
        right = build_node(ctx, right_refs, offset + mid, depth + 1, nodes, scratch);
    }
    nodes[index as usize] = Node::Inner { bounds, left, right };
    index
}

/// Append a subtree built with local indices; returns its root's new index.
fn append(nodes: &mut Vec<Node>, sub: Vec<Node>) -> u32 {
    let base = nodes.len() as u32;
    nodes.extend(sub.into_iter().map(|n| match n {
        Node::Inner { bounds, left, right } => Node::Inner { bounds, left: left + base, right: right + base },
        leaf => leaf,
    }));
    base
}

#[cfg(feature = "parallel")]
fn join<A: Send, B: Send>(a: impl FnOnce() -> A + Send, b: impl FnOnce() -> B + Send) -> (A, B) {
    rayon::join(a, b)
}

#[cfg(not(feature = "parallel"))]
fn join<A, B>(a: impl FnOnce() -> A, b: impl FnOnce() -> B) -> (A, B) {
    (a(), b())
}

#[cfg(test)]
mod tests {
    use super::*;

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
