//! Flattening in parallel: the host's per-texel and per-ray lists (a frame's millions of texels,
//! a Whitted wave's paths) written by every thread.

use rayon::prelude::*;

/// The outputs of every item of `items`, in order: `count(i, &items[i])` of them each, handed by
/// `fill(i, &items[i], push)` to `push` one by one. Rayon's unindexed `collect` (`filter_map`,
/// `flat_map_iter`) appends its pieces on one thread, which first-touches every page of the result
/// there; here pieces of items are counted, the result is filled with `placeholder` by every thread,
/// and each piece writes its own slice of it.
///
/// # Panics
/// If `fill` hands out more items than `count` said (a caller's bug).
pub fn par_flatten<S: Sync, T: Copy + Send + Sync>(
    items: &[S],
    placeholder: T,
    count: impl Fn(usize, &S) -> usize + Sync,
    fill: impl Fn(usize, &S, &mut dyn FnMut(T)) + Sync,
) -> Vec<T> {
    let piece = piece_len(items.len());
    let counts: Vec<usize> = items
        .par_chunks(piece)
        .enumerate()
        .map(|(k, p)| p.iter().enumerate().map(|(j, s)| count(k * piece + j, s)).sum())
        .collect();
    let mut out: Vec<T> = (0..counts.iter().sum::<usize>()).into_par_iter().map(|_| placeholder).collect();
    let slots = split_by_counts(&mut out, counts.iter().copied());
    items.par_chunks(piece).enumerate().zip(slots).for_each(|((k, p), slot)| {
        let mut at = 0;
        for (j, s) in p.iter().enumerate() {
            fill(k * piece + j, s, &mut |t| {
                slot[at] = t;
                at += 1;
            });
        }
        debug_assert_eq!(at, slot.len(), "fill handed out fewer items than count said");
    });
    out
}

/// Items a piece of a parallel pass over `len` items takes: sixteen pieces a thread for balance,
/// at most 16,384 items a piece.
#[must_use]
pub fn piece_len(len: usize) -> usize {
    (len / (16 * rayon::current_num_threads())).clamp(1, 1 << 14)
}

/// `all` split into consecutive slices of `counts` elements each.
///
/// # Panics
/// If the counts add up to more than `all.len()`.
pub fn split_by_counts<T>(mut all: &mut [T], counts: impl IntoIterator<Item = usize>) -> Vec<&mut [T]> {
    let mut out = Vec::new();
    for n in counts {
        let (head, tail) = all.split_at_mut(n);
        out.push(head);
        all = tail;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_every_output_in_order_across_pieces() {
        // Items yielding 0, 1 or 2 outputs, and items yielding many (a beam's texels).
        for len in [0, 1, 17, 3 * (1 << 14) + 5, 100_000] {
            let items: Vec<u64> = (0..len).collect();
            let each = |i: usize, x: u64| {
                [(x % 3 == 0).then_some((i, x)), (x % 5 == 0).then_some((i, x + 1))].into_iter().flatten()
            };
            let serial: Vec<(usize, u64)> = items.iter().enumerate().flat_map(|(i, &x)| each(i, x)).collect();
            let flat = par_flatten(&items, (0, 0), |i, &x| each(i, x).count(), |i, &x, push| each(i, x).for_each(push));
            assert_eq!(flat, serial);
            let many = par_flatten(&items, 0, |_, &x| (x % 7) as usize, |_, &x, push| (0..x % 7).for_each(push));
            assert_eq!(many, items.iter().flat_map(|&x| 0..x % 7).collect::<Vec<_>>());
        }
    }
}
