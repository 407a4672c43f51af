//! Binned split search shared by the binary and the 8-wide builders (Wald 2007): primitive
//! references as two `Vec4`s, one pass that bins x, y and z together, a cost sweep under a
//! pluggable area measure (SAH, or the PAH of 004), and a partition that returns the children's
//! boxes and centroid boxes so that no node needs another pass over its references.
//!
//! Splitting-plane facing (004) adds two directions that are not axes; those go through a slower
//! generic path with dot products. Both paths bin a reference the same way in the search and in
//! the partition (one function each), so a split always separates what it measured. Nodes of a
//! few references are not binned: every partition of them is costed (`small.rs`).

use crate::options::{BuildOptions, Heuristic, RayDistribution};
use beam_math::Aabb;
use beam_math::glam::{Vec3, Vec4};
use beam_math::heuristics::{projected_area_orthographic_fast, projected_area_perspective_fast, surface_area};

mod directions;
mod partition;
mod refs;
mod small;
mod sweep;

pub(crate) use partition::{median_split, partition};
pub(crate) use refs::{Box4, PrimRef, Record, make_refs, record_of};
use small::{SMALL_MAX, SmallSplit, find_small};
use sweep::{sweep, sweep_axes};

/// Largest number of bins.
pub(crate) const MAX_BINS: usize = 32;
/// Nodes with more references than this bin in parallel chunks.
pub(crate) const PARALLEL_BINNING: usize = 32_768;

/// Per-build constants.
pub(crate) struct Context {
    pub options: BuildOptions,
    pub(crate) directions: [Vec3; 5],
    direction_count: usize,
    /// Leaves are intersected in blocks of `1 << block_shift` triangles: the cost of `n`
    /// references is that of `⌈n / 2^block_shift⌉` blocks.
    pub block_shift: u32,
    /// Where the candidate planes lie.
    pub grid: Grid,
}

/// Where a binned search puts its `bins − 1` candidate planes across the centroids' range.
/// Neither is better everywhere: with [`Grid::Equal`] the direct 8-wide builder's Sponza tree
/// costs its shadow rays 5% fewer box and 16% fewer triangle tests (and traces them 6% faster),
/// and the collapsed tree's Sponza rays trace 3–4% faster; on the conference room the collapsed
/// tree costs primary rays 21% more box tests with it and traces 1–5% slower (spatial splits
/// there: 8–17% faster). Sponza's shadow rays, the slowest against Embree, decide: every 8-wide
/// tree bins on it (`docs/benchmarks.md`).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Grid {
    /// Bin `k` holds the coordinates nearest to the `k`-th of `bins` points spanning the range:
    /// the first and last bins are half as wide as the others. The binary BVH's (beams, GPU).
    Centred,
    /// `bins` bins of equal width over the range widened by 1%, as Embree's binner makes them.
    /// Every 8-wide tree's.
    Equal,
}

impl Grid {
    /// The scale from centroid coordinates (less the range's low end) to bin coordinates, for a
    /// range of width `width`.
    fn scale(self, bins: usize, width: f32) -> f32 {
        match self {
            Grid::Centred => (bins - 1) as f32 / width,
            Grid::Equal => 0.99 * bins as f32 / width,
        }
    }

    /// Subtracted from a bin coordinate before rounding it to the nearest integer: the bin is the
    /// nearest point (`Centred`) or the floor (`Equal`, but at ties).
    fn shift(self) -> f32 {
        match self {
            Grid::Centred => 0.0,
            Grid::Equal => 0.5,
        }
    }
}

impl Context {
    pub fn new(options: &BuildOptions, block_shift: u32, grid: Grid) -> Self {
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
        Self { options, directions, direction_count, block_shift, grid }
    }

    /// Cost units of a leaf of `n` references.
    #[inline(always)]
    pub fn blocks(&self, n: usize) -> f32 {
        ((n + (1 << self.block_shift) - 1) >> self.block_shift) as f32
    }

    /// The area measure for the children of a node with box `parent`: projected area when the
    /// distribution applies to the whole node, surface area otherwise (004's fallback).
    pub fn measure(&self, parent: Aabb) -> Measure {
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

/// How a node's area is measured.
#[derive(Clone, Copy)]
pub(crate) enum Measure {
    Surface,
    Orthographic(Vec3),
    Perspective(Vec3, Vec3),
}

impl Measure {
    /// [`Measure::area`] of a box in `Vec4`s: the surface area without the conversion (the same
    /// operations as `surface_area`, an empty box included: its clamped extent is 0).
    #[inline(always)]
    pub fn area4(self, b: Box4) -> f32 {
        match self {
            Measure::Surface => {
                let e = (b.hi - b.lo).max(Vec4::ZERO);
                2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
            }
            _ => self.area(b.aabb()),
        }
    }

    pub fn area(self, b: Aabb) -> f32 {
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

/// What a split separates along.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Plane {
    /// Coordinate `axis` of the doubled centroid.
    Axis(usize),
    /// The doubled centroid's projection on a direction.
    Direction(Vec3),
}

/// The best partition of a node: references with bin `< bin` go left.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Split {
    pub(crate) plane: Plane,
    pub(crate) lo: f32,
    pub(crate) scale: f32,
    /// [`Grid::shift`].
    pub(crate) shift: f32,
    pub(crate) bins: usize,
    pub(crate) bin: usize,
    /// `A(L)·blocks(N_L) + A(R)·blocks(N_R)` under the node's measure.
    pub cost: f32,
}

impl Split {
    #[inline(always)]
    pub(crate) fn bin_of(&self, r: &PrimRef) -> usize {
        let x = match self.plane {
            Plane::Axis(a) => r.centroid2().to_array()[a],
            Plane::Direction(d) => r.centroid2().truncate().dot(d),
        };
        bin_index(((x - self.lo) * self.scale - self.shift).min((self.bins - 1) as f32))
    }
}

/// Added to a bin coordinate in `[0, 2^22)`, this puts its value rounded to the nearest integer in
/// the low mantissa bits: a float-to-integer conversion without the checks of `as`.
const ROUNDER: f32 = 12_582_912.0;

/// The bin of bin coordinate `x` less the grid's shift (at most `bins − 1`): `x` rounded to the
/// nearest integer. The vector binning in [`find_split`] computes the same for three lanes at
/// once.
#[inline(always)]
fn bin_index(x: f32) -> usize {
    ((x + ROUNDER).to_bits() - ROUNDER.to_bits()) as usize
}

/// Bin contents of the three axes.
#[derive(Clone, Copy)]
pub(crate) struct Bins {
    bounds: [[Box4; MAX_BINS]; 3],
    counts: [[u32; MAX_BINS]; 3],
}

impl Bins {
    pub const EMPTY: Self = Self { bounds: [[Box4::EMPTY; MAX_BINS]; 3], counts: [[0; MAX_BINS]; 3] };

    fn clear(&mut self, bins: usize) {
        for a in 0..3 {
            self.bounds[a][..bins].fill(Box4::EMPTY);
            self.counts[a][..bins].fill(0);
        }
    }

    fn merge_first(&mut self, o: &Self, bins: usize) {
        for a in 0..3 {
            for b in 0..bins {
                self.bounds[a][b] = self.bounds[a][b].union(o.bounds[a][b]);
                self.counts[a][b] += o.counts[a][b];
            }
        }
    }

    fn merge(mut self, o: Self) -> Self {
        for a in 0..3 {
            for b in 0..MAX_BINS {
                self.bounds[a][b] = self.bounds[a][b].union(o.bounds[a][b]);
                self.counts[a][b] += o.counts[a][b];
            }
        }
        self
    }
}

/// `f` over chunks of `refs` merged with `merge`, in parallel for large slices.
pub(crate) fn reduce_chunks<T: Send + Sync + Copy>(
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

/// A split of a node's references: binned, or exact for a small node.
#[derive(Clone, Copy, Debug)]
pub(crate) enum NodeSplit {
    Binned(Split),
    Small(SmallSplit),
}

impl NodeSplit {
    /// `A(L)·blocks(N_L) + A(R)·blocks(N_R)` under the node's measure.
    pub fn cost(&self) -> f32 {
        match self {
            NodeSplit::Binned(s) => s.cost,
            NodeSplit::Small(s) => s.cost,
        }
    }

    /// Partition `refs` (those the split was found for) in place; returns the number on the left
    /// and the records of both sides.
    pub fn partition(&self, refs: &mut [PrimRef]) -> (usize, Record, Record) {
        match self {
            NodeSplit::Binned(s) => partition(refs, s),
            NodeSplit::Small(s) => s.partition(refs),
        }
    }
}

/// The cheapest split of `refs` (summarised by `record`) under `measure`: over every partition
/// for at most [`SMALL_MAX`] references, else binned (`None` when every centroid coincides).
pub(crate) fn find_node_split(
    ctx: &Context,
    refs: &[PrimRef],
    record: &Record,
    measure: Measure,
    scratch: &mut Bins,
) -> Option<NodeSplit> {
    if refs.len() <= SMALL_MAX {
        return Some(NodeSplit::Small(find_small(ctx, refs, measure)));
    }
    find_split(ctx, refs, record, measure, scratch).map(NodeSplit::Binned)
}

/// The cheapest binned split of `refs` (summarised by `record`) under `measure`, or `None` when
/// every centroid coincides.
pub(crate) fn find_split(
    ctx: &Context,
    refs: &[PrimRef],
    record: &Record,
    measure: Measure,
    scratch: &mut Bins,
) -> Option<Split> {
    // Small nodes need few bins, and most nodes are small: 4 + n/20 as Embree's binner (the
    // sweep over 32 bins cost as much as the binning itself on small nodes; the trees traced as
    // fast).
    let bins = ctx.options.bins.min(4 + refs.len() / 20);
    if ctx.direction_count > 3 {
        return directions::find_split(ctx, refs, measure, bins);
    }
    let (lo, hi) = (record.centroids.lo, record.centroids.hi);
    let usable = |a: usize| hi[a] - lo[a] > 1e-20 * (lo[a].abs() + hi[a].abs()).max(1e-30);
    let last = (bins - 1) as f32;
    let shift = ctx.grid.shift();
    let scale = Vec4::new(
        if usable(0) { ctx.grid.scale(bins, hi.x - lo.x) } else { 0.0 },
        if usable(1) { ctx.grid.scale(bins, hi.y - lo.y) } else { 0.0 },
        if usable(2) { ctx.grid.scale(bins, hi.z - lo.z) } else { 0.0 },
        0.0,
    );
    // `Split::bin_of` (`bin_index` of the clamped coordinate), three lanes at once.
    let add = |p: &PrimRef, out: &mut Bins| {
        let x = (p.centroid2() - lo) * scale - Vec4::splat(shift);
        let b = (x.min(Vec4::splat(last)) + ROUNDER).to_array();
        for a in 0..3 {
            let k = (b[a].to_bits() - ROUNDER.to_bits()) as usize;
            out.bounds[a][k] = out.bounds[a][k].union(p.bounds());
            out.counts[a][k] += 1;
        }
    };
    let bin_chunk = |chunk: &[PrimRef], out: &mut Bins| {
        out.clear(bins);
        if chunk.len() < 256 {
            chunk.iter().for_each(|p| add(p, out));
            return;
        }
        // Neighbours in memory often fall into the same bin: alternating between two sets of
        // bins halves the chains of read-modify-writes on one bin.
        let mut other = Bins::EMPTY;
        other.clear(bins);
        let pairs = chunk.chunks_exact(2);
        let rest = pairs.remainder();
        for pair in pairs {
            add(&pair[0], out);
            add(&pair[1], &mut other);
        }
        rest.iter().for_each(|p| add(p, out));
        out.merge_first(&other, bins);
    };
    if ctx.options.parallel && refs.len() > PARALLEL_BINNING {
        let chunk = |c: &[PrimRef]| {
            let mut out = Bins::EMPTY;
            bin_chunk(c, &mut out);
            out
        };
        *scratch = reduce_chunks(refs, true, Bins::EMPTY, chunk, Bins::merge);
    } else {
        bin_chunk(refs, scratch);
    }
    let probe = |a: usize| Split { plane: Plane::Axis(a), lo: lo[a], scale: scale[a], shift, bins, bin: 0, cost: 0.0 };
    let mut best: Option<Split> = None;
    if let Measure::Surface = measure {
        sweep_axes(ctx, scratch, bins, refs.len(), scale, probe, &mut best);
        return best;
    }
    for a in 0..3 {
        if scale[a] != 0.0 {
            sweep(
                ctx,
                measure,
                &scratch.bounds[a][..bins],
                &scratch.counts[a][..bins],
                refs.len(),
                probe(a),
                &mut best,
            );
        }
    }
    best
}
