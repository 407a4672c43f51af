//! The binned split search with splitting-plane facing (004): five directions (x, y, z and two
//! perpendicular to the rays), binned through dot products of the doubled centroids.

use super::refs::{Box4, PrimRef, reduce_chunks};
use super::split::{Context, MAX_BINS, Measure, Plane, Split};
use super::sweep::sweep;

/// [`find_split`] with splitting-plane facing: five directions, binned through dot products.
pub(super) fn find_split(ctx: &Context, refs: &[PrimRef], measure: Measure, bins: usize) -> Option<Split> {
    const D: usize = 5;
    let dirs = &ctx.directions[..D];
    let parallel = ctx.options.parallel;
    let ranges = reduce_chunks(
        refs,
        parallel,
        [(f32::INFINITY, f32::NEG_INFINITY); D],
        |chunk| {
            let mut r = [(f32::INFINITY, f32::NEG_INFINITY); D];
            for p in chunk {
                let c = p.centroid2().truncate();
                for (d, dir) in dirs.iter().enumerate() {
                    let x = c.dot(*dir);
                    r[d] = (r[d].0.min(x), r[d].1.max(x));
                }
            }
            r
        },
        |a, b| core::array::from_fn(|d| (a[d].0.min(b[d].0), a[d].1.max(b[d].1))),
    );
    let probes: [Option<Split>; D] = core::array::from_fn(|d| {
        let (lo, hi) = ranges[d];
        (hi - lo > 1e-20 * (lo.abs() + hi.abs()).max(1e-30)).then(|| Split {
            plane: Plane::Direction(dirs[d]),
            lo,
            scale: ctx.grid.scale(bins, hi - lo),
            shift: ctx.grid.shift(),
            bins,
            bin: 0,
            cost: 0.0,
        })
    });
    type DirBins = [([Box4; MAX_BINS], [u32; MAX_BINS]); D];
    let empty: DirBins = [([Box4::EMPTY; MAX_BINS], [0; MAX_BINS]); D];
    let binned = reduce_chunks(
        refs,
        parallel,
        empty,
        |chunk| {
            let mut out = empty;
            for p in chunk {
                for (d, probe) in probes.iter().enumerate() {
                    if let Some(probe) = probe {
                        let b = probe.bin_of(p);
                        out[d].0[b] = out[d].0[b].union(p.bounds());
                        out[d].1[b] += 1;
                    }
                }
            }
            out
        },
        |mut a, b| {
            for d in 0..D {
                for k in 0..MAX_BINS {
                    a[d].0[k] = a[d].0[k].union(b[d].0[k]);
                    a[d].1[k] += b[d].1[k];
                }
            }
            a
        },
    );
    let mut best = None;
    for (d, probe) in probes.iter().enumerate() {
        if let Some(probe) = probe {
            sweep(ctx, measure, &binned[d].0[..bins], &binned[d].1[..bins], refs.len(), *probe, &mut best);
        }
    }
    best
}
