//! Checks of the bench commands' arguments.

/// An image side of a benchmark: 1 to 16384.
pub(super) fn side(option: &str, v: u32) -> Result<(), String> {
    match v {
        1..=crate::plan::MAX_SIDE => Ok(()),
        _ => Err(format!("{option} {v} out of range (1 to {})", crate::plan::MAX_SIDE)),
    }
}
