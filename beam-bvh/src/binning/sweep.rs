//! The cost sweeps over a node's bins: for every plane between two bins, the cost
//! `A(L)·blocks(N_L) + A(R)·blocks(N_R)` of the split it makes, and the cheapest of them.

use super::refs::Box4;
use super::split::{Bins, Context, MAX_BINS, Measure, Split};
use beam_math::glam::{UVec4, Vec4};

/// The cost sweep over one direction's bins: from the right, then from the left; keeps the
/// cheapest split in `best` (the first of equal costs).
pub(crate) fn sweep(
    ctx: &Context,
    measure: Measure,
    bounds: &[Box4],
    counts: &[u32],
    n_total: usize,
    probe: Split,
    best: &mut Option<Split>,
) {
    let bins = bounds.len();
    let mut right_cost = [0.0f32; MAX_BINS];
    let mut acc = Box4::EMPTY;
    let mut n = 0usize;
    for b in (1..bins).rev() {
        acc = acc.union(bounds[b]);
        n += counts[b] as usize;
        right_cost[b] = measure.area4(acc) * ctx.blocks(n);
    }
    let mut acc = Box4::EMPTY;
    let mut n = 0usize;
    for b in 1..bins {
        acc = acc.union(bounds[b - 1]);
        n += counts[b - 1] as usize;
        if n == 0 || n == n_total {
            continue;
        }
        let cost = measure.area4(acc) * ctx.blocks(n) + right_cost[b];
        if best.as_ref().is_none_or(|s| cost < s.cost) {
            *best = Some(Split { bin: b, cost, ..probe });
        }
    }
}

/// [`sweep`] of the x, y and z axes at once under the surface area, lane `a` of each vector
/// holding axis `a`: the same operations lane by lane, so the same costs to the bit, and the
/// same choice (the first of equal costs, axis by axis). Axes whose `scale` is 0 are skipped.
pub(crate) fn sweep_axes(
    ctx: &Context,
    binned: &Bins,
    bins: usize,
    n_total: usize,
    scale: Vec4,
    probe: impl Fn(usize) -> Split,
    best: &mut Option<Split>,
) {
    // Surface areas of the three boxes, one per lane (`Measure::area4` lane by lane).
    let areas = |acc: &[Box4; 3]| {
        let e = acc.map(|b| (b.hi - b.lo).max(Vec4::ZERO));
        let ex = Vec4::new(e[0].x, e[1].x, e[2].x, 0.0);
        let ey = Vec4::new(e[0].y, e[1].y, e[2].y, 0.0);
        let ez = Vec4::new(e[0].z, e[1].z, e[2].z, 0.0);
        2.0 * (ex * ey + ey * ez + ez * ex)
    };
    let round = UVec4::splat((1 << ctx.block_shift) - 1);
    let blocks = |n: UVec4| ((n + round) >> ctx.block_shift).as_vec4();
    let counts = |b: usize| UVec4::new(binned.counts[0][b], binned.counts[1][b], binned.counts[2][b], 0);
    let union = |acc: &mut [Box4; 3], b: usize| {
        for (a, acc) in acc.iter_mut().enumerate() {
            *acc = acc.union(binned.bounds[a][b]);
        }
    };
    let mut right_cost = [Vec4::ZERO; MAX_BINS];
    let mut acc = [Box4::EMPTY; 3];
    let mut n = UVec4::ZERO;
    for b in (1..bins).rev() {
        union(&mut acc, b);
        n += counts(b);
        right_cost[b] = areas(&acc) * blocks(n);
    }
    let mut cost = [Vec4::ZERO; MAX_BINS];
    // Bit `a` set where the plane splits axis `a` with both sides non-empty.
    let mut splits = [0u32; MAX_BINS];
    let mut acc = [Box4::EMPTY; 3];
    let mut n = UVec4::ZERO;
    let total = UVec4::splat(n_total as u32);
    for b in 1..bins {
        union(&mut acc, b - 1);
        n += counts(b - 1);
        cost[b] = areas(&acc) * blocks(n) + right_cost[b];
        splits[b] = !(n.cmpeq(UVec4::ZERO) | n.cmpeq(total)).bitmask();
    }
    for a in 0..3 {
        if scale[a] == 0.0 {
            continue;
        }
        for b in 1..bins {
            let c = cost[b][a];
            if splits[b] >> a & 1 != 0 && best.as_ref().is_none_or(|s| c < s.cost) {
                *best = Some(Split { bin: b, cost: c, ..probe(a) });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binning::{Grid, Plane};
    use crate::options::BuildOptions;
    use crate::traverse::tests::unit_rng;

    /// On random bins (empty ones, single-axis nodes and blocks of four included), the three-lane
    /// sweep picks the split the one-axis sweep picks, at the same cost to the bit.
    #[test]
    fn sweeping_three_axes_at_once_equals_one_at_a_time() {
        let mut rnd = unit_rng(11);
        for trial in 0..3000 {
            let ctx = Context::new(&BuildOptions::sah(), (trial % 2) as u32 * 2, Grid::Equal);
            let bins = 2 + trial % (MAX_BINS - 1);
            // Each axis bins the same references: its counts are axis 0's, rotated.
            let first: Vec<u32> = (0..bins).map(|_| if rnd() < 0.3 { 0 } else { 1 + (rnd() * 9.0) as u32 }).collect();
            let n_total = first.iter().sum::<u32>() as usize;
            let mut binned = Bins::EMPTY;
            for a in 0..3 {
                for b in 0..bins {
                    let count = first[(b + 7 * a) % bins];
                    if count > 0 {
                        let lo = Vec4::new(rnd(), rnd(), rnd(), 0.0) * 10.0;
                        binned.bounds[a][b] = Box4 { lo, hi: lo + Vec4::new(rnd(), rnd(), rnd(), 0.0) };
                        binned.counts[a][b] = count;
                    }
                }
            }
            let scale = Vec4::new(1.0, if trial % 5 == 0 { 0.0 } else { 1.0 }, 1.0, 0.0);
            let probe = |a: usize| Split {
                plane: Plane::Axis(a),
                lo: 0.0,
                scale: scale[a],
                shift: 0.0,
                bins,
                bin: 0,
                cost: 0.0,
            };
            let mut one = None;
            for a in 0..3 {
                if scale[a] != 0.0 {
                    let (bounds, counts) = (&binned.bounds[a][..bins], &binned.counts[a][..bins]);
                    sweep(&ctx, Measure::Surface, bounds, counts, n_total, probe(a), &mut one);
                }
            }
            let mut three = None;
            sweep_axes(&ctx, &binned, bins, n_total, scale, probe, &mut three);
            let key = |s: Option<Split>| s.map(|s| (format!("{:?}", s.plane), s.bin, s.cost.to_bits()));
            assert_eq!(key(one), key(three), "trial {trial}");
        }
    }
}
