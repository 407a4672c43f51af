//! Binned split search shared by the binary and the 8-wide builders (Wald 2007): primitive
//! references as two `Vec4`s, one pass that bins x, y and z together, a cost sweep under a
//! pluggable area measure (SAH, or the PAH of 004), and a partition that returns the children's
//! boxes and centroid boxes so that no node needs another pass over its references.
//!
//! Splitting-plane facing (004) adds two directions that are not axes; those go through a slower
//! generic path with dot products. Both paths bin a reference the same way in the search and in
//! the partition (one function each), so a split always separates what it measured. Nodes of a
//! few references are not binned: every partition of them is costed (`small.rs`).

use beam_math::glam::Vec4;

mod directions;
mod partition;
mod refs;
mod small;
mod split;
mod sweep;

pub(crate) use partition::{median_split, partition};
use refs::PARALLEL_BINNING;
pub(crate) use refs::{Box4, PrimRef, Record, make_refs, record_of, reduce_chunks};
use small::{SMALL_MAX, SmallSplit, find_small};
use split::ROUNDER;
pub(crate) use split::{Bins, Context, Grid, Measure, Plane, Split};
use sweep::{sweep, sweep_axes};

/// A split of a node's references: binned, or exact for a small node.
#[derive(Clone, Copy, Debug)]
pub(crate) enum NodeSplit {
    Binned(Split),
    Small(SmallSplit),
}

impl NodeSplit {
    /// `A(L)·blocks(N_L) + A(R)·blocks(N_R)` under the node's measure.
    pub(crate) fn cost(&self) -> f32 {
        match self {
            NodeSplit::Binned(s) => s.cost,
            NodeSplit::Small(s) => s.cost,
        }
    }

    /// Partition `refs` (those the split was found for) in place; returns the number on the left
    /// and the records of both sides.
    pub(crate) fn partition(&self, refs: &mut [PrimRef]) -> (usize, Record, Record) {
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
