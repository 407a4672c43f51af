//! Parallel sums that come out the same, bit for bit, on any number of threads: floating-point
//! addition is not associative, so a rayon `fold`/`reduce` (whose grouping follows the work
//! stealing) gives run-to-run differences in the last bits. Photon and caustic maps are summed this
//! way so that a render farm's processes, each on its own machine, agree with a one-process render.

use rayon::prelude::*;

/// Chunks the jobs are folded in: enough to keep every thread busy, few enough that merging them
/// costs little next to the jobs.
pub const CHUNKS: usize = 128;

/// `jobs` folded into accumulators a fixed chunk at a time (up to [`CHUNKS`] contiguous chunks,
/// in parallel), and the chunks' accumulators merged into `empty()` in chunk order. At most one
/// accumulator per thread, plus the total, is alive at once.
pub fn fold_in_order<J: Sync, A: Send>(
    jobs: &[J],
    empty: impl Fn() -> A + Sync,
    fold: impl Fn(A, &J) -> A + Sync,
    mut merge: impl FnMut(&mut A, A),
) -> A {
    let size = jobs.len().div_ceil(CHUNKS).max(1);
    let chunks: Vec<&[J]> = jobs.chunks(size).collect();
    let mut total = empty();
    for round in chunks.chunks(rayon::current_num_threads().max(1)) {
        let parts: Vec<A> = round.par_iter().map(|chunk| chunk.iter().fold(empty(), &fold)).collect();
        for part in parts {
            merge(&mut total, part);
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_do_not_depend_on_the_threads() {
        let jobs: Vec<f32> = (0..10_000).map(|i| 1.0 / (1.0 + i as f32).powf(1.3)).collect();
        let sum = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| fold_in_order(&jobs, || 0.0f32, |a, j| a + j, |t, a| *t += a))
        };
        let one = sum(1);
        assert!([2, 3, 7, 16].iter().all(|&t| sum(t).to_bits() == one.to_bits()));
        assert!((one - jobs.iter().sum::<f32>()).abs() < 1e-4);
    }
}
