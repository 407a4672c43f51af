//! Summaries of repeated measurements.

/// The middle value of `v` (the upper of the two middle ones for an even length; 0 for none).
pub(super) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}
