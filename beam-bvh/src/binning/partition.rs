//! Partitions of a node's references, with the records of both sides.

use super::refs::{PrimRef, Record, record_of};
use super::split::Split;

/// Partition `refs` by `split` in place (stable for neither side); returns the number on the left
/// and the records of both sides.
pub(crate) fn partition(refs: &mut [PrimRef], split: &Split) -> (usize, Record, Record) {
    partition_by(refs, |r| split.bin_of(r) < split.bin)
}

/// Partition `refs` in place by `left`; returns the number on the left and both records.
///
/// Branch-free (Lomuto's scheme with an unconditional swap): which side a reference goes to is
/// data, not a branch to predict, and binned splits send neighbours either way about as often.
/// The records are two streaming passes after.
pub(crate) fn partition_by(refs: &mut [PrimRef], left: impl Fn(&PrimRef) -> bool) -> (usize, Record, Record) {
    let mut i = 0usize;
    for j in 0..refs.len() {
        let x = refs[j];
        let go = left(&x);
        refs[j] = refs[i];
        refs[i] = x;
        i += usize::from(go);
    }
    debug_assert!(refs[..i].iter().all(&left) && !refs[i..].iter().any(&left));
    (i, record_of(&refs[..i], false), record_of(&refs[i..], false))
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
