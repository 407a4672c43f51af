//! The buffers of a winding pass ([`super::silhouette`]), kept by a thread from one pass to the next.

use beam_math::polybeam::{Arrangement, WindingEdge};

/// Buffers a thread reuses from one pass to the next.
#[derive(Default)]
pub(crate) struct WindingScratch {
    /// Every projected edge of the cycle (for the anchor's winding number).
    pub(super) cycle: Vec<WindingEdge>,
    /// Those over the light's bounding rectangle.
    pub(super) over: Vec<WindingEdge>,
    pub(super) arrangement: Box<Arrangement>,
}
