//! Limits of the mesh readers, shared by the readers and the errors that name them.

/// Most corners of a non-convex face (ear clipping takes up to cubic time in the corners).
pub const MAX_NONCONVEX_CORNERS: usize = 256;
