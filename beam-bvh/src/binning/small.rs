//! The exact split search for the smallest nodes: every partition of at most [`SMALL_MAX`]
//! references into two non-empty sides, costed under the node's measure (binning, the
//! approximation, costs more than this exhaustive search on nodes this small, and most nodes of a
//! binary tree are). Its split is never worse than a binned one: that is one of the partitions it
//! costs.

use super::refs::{Box4, PrimRef, Record};
use super::split::{Context, Measure};

/// Nodes of at most this many references are split by [`find_small`].
pub(crate) const SMALL_MAX: usize = 4;

/// The cheapest partition of a small node: bit `i` of `left` set when reference `i` goes left.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SmallSplit {
    left: u8,
    /// `A(L)·blocks(N_L) + A(R)·blocks(N_R)` under the node's measure.
    pub cost: f32,
}

/// The cheapest partition of `refs` (2 to [`SMALL_MAX`] of them) under `measure`; the first of
/// equal costs in the order of the left side's bit mask (the first when every cost is infinite).
pub(crate) fn find_small(ctx: &Context, refs: &[PrimRef], measure: Measure) -> SmallSplit {
    let n = refs.len();
    debug_assert!((2..=SMALL_MAX).contains(&n));
    // The union of every subset of the references, by bit mask.
    let mut union = [Box4::EMPTY; 1 << SMALL_MAX];
    for m in 1..1usize << n {
        union[m] = union[m & (m - 1)].union(refs[m.trailing_zeros() as usize].bounds());
    }
    let all = (1usize << n) - 1;
    let mut best = SmallSplit { left: 1, cost: f32::INFINITY };
    // The last reference goes right: every partition once.
    for m in 1..1usize << (n - 1) {
        let count = m.count_ones() as usize;
        let cost = measure.area4(union[m]) * ctx.blocks(count) + measure.area4(union[all ^ m]) * ctx.blocks(n - count);
        if m == 1 || cost < best.cost {
            best = SmallSplit { left: m as u8, cost };
        }
    }
    best
}

impl SmallSplit {
    /// Partition `refs` (those [`find_small`] was given) in place; returns the number on the left
    /// and the records of both sides.
    pub(crate) fn partition(&self, refs: &mut [PrimRef]) -> (usize, Record, Record) {
        let mut i = 0;
        for j in 0..refs.len() {
            if self.left >> j & 1 != 0 {
                refs.swap(i, j);
                i += 1;
            }
        }
        let mid = self.left.count_ones() as usize;
        debug_assert_eq!(i, mid);
        let (mut l, mut r) = (Record::EMPTY, Record::EMPTY);
        refs[..mid].iter().for_each(|p| l.add(p));
        refs[mid..].iter().for_each(|p| r.add(p));
        (mid, l, r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binning::{Bins, Grid, find_split, partition, record_of};
    use crate::options::BuildOptions;
    use crate::traverse::tests::unit_rng;
    use beam_math::Triangle;
    use beam_math::glam::Vec3;

    /// On random nodes of 2 to 4 triangles: the search's cost is the cost of the partition it
    /// makes, no binned split is cheaper, and the records are those of the two sides.
    #[test]
    fn small_split_is_exact_and_never_worse_than_binning() {
        let ctx = Context::new(&BuildOptions::sah(), 0, Grid::Equal);
        let mut rnd = unit_rng(7);
        let mut scratch = Box::new(Bins::EMPTY);
        for trial in 0..2000 {
            let n = 2 + trial % (SMALL_MAX - 1);
            let tris: Vec<Triangle> = (0..n)
                .map(|_| {
                    let o = Vec3::new(rnd(), rnd(), rnd()) * 10.0;
                    let e = |r: &mut dyn FnMut() -> f32| Vec3::new(r(), r(), r());
                    Triangle::new(o, o + e(&mut rnd), o + e(&mut rnd))
                })
                .collect();
            let refs: Vec<PrimRef> = tris
                .iter()
                .enumerate()
                .map(|(i, t)| PrimRef::with_box(beam_math::Aabb::from_points(&t.v), i as u32))
                .collect();
            let record = record_of(&refs, false);
            let measure = Measure::Surface;
            let small = find_small(&ctx, &refs, measure);
            let mut split = refs.clone();
            let (mid, l, r) = small.partition(&mut split);
            assert!(mid > 0 && mid < n);
            let cost = |p: &[PrimRef]| measure.area4(record_of(p, false).bounds) * ctx.blocks(p.len());
            assert_eq!(small.cost, cost(&split[..mid]) + cost(&split[mid..]));
            for (side, rec) in [(&split[..mid], l), (&split[mid..], r)] {
                let want = record_of(side, false);
                assert_eq!((rec.bounds.lo, rec.bounds.hi), (want.bounds.lo, want.bounds.hi));
            }
            let mut kept: Vec<u32> = split.iter().map(PrimRef::index).collect();
            kept.sort_unstable();
            assert_eq!(kept, (0..n as u32).collect::<Vec<_>>());
            if let Some(binned) = find_split(&ctx, &refs, &record, measure, &mut scratch) {
                let mut b = refs.clone();
                let (m, _, _) = partition(&mut b, &binned);
                assert!(small.cost <= cost(&b[..m]) + cost(&b[m..]), "trial {trial}");
            }
        }
    }
}
