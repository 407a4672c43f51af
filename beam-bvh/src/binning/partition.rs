//! Partitions of a node's references, with the records of both sides.

use super::{PrimRef, Record, Split, record_of};

/// Partition `refs` by `split` in place (stable for neither side); returns the number on the left
/// and the records of both sides.
pub(crate) fn partition(refs: &mut [PrimRef], split: &Split) -> (usize, Record, Record) {
    partition_by(refs, |r| split.bin_of(r) < split.bin)
}

/// Partition `refs` in place by `left`; returns the number on the left and both records.
pub(crate) fn partition_by(refs: &mut [PrimRef], left: impl Fn(&PrimRef) -> bool) -> (usize, Record, Record) {
    let (mut l, mut r) = (Record::EMPTY, Record::EMPTY);
    let (mut i, mut j) = (0usize, refs.len());
    // Hoare: refs[..i] go left, refs[j..] go right.
    loop {
        while i < j && left(&refs[i]) {
            l.add(&refs[i]);
            i += 1;
        }
        while i < j && !left(&refs[j - 1]) {
            r.add(&refs[j - 1]);
            j -= 1;
        }
        if i >= j {
            break;
        }
        refs.swap(i, j - 1);
        l.add(&refs[i]);
        r.add(&refs[j - 1]);
        i += 1;
        j -= 1;
    }
    debug_assert!(refs[..i].iter().all(&left) && !refs[i..].iter().any(&left));
    (i, l, r)
}

/// Split `refs` at their median along the longest axis of the centroid box (when binning cannot
/// separate them or the depth bound is reached).
pub(crate) fn median_split(refs: &mut [PrimRef], record: &Record) -> (usize, Record, Record) {
    let e = record.centroids.hi - record.centroids.lo;
    let axis = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let mid = refs.len() / 2;
    refs.select_nth_unstable_by(mid, |a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
    (mid, record_of(&refs[..mid], false), record_of(&refs[mid..], false))
}
