//! # beam-bvh
//!
//! Bounding volume hierarchies for beam: builders, layouts and traversal. Work in progress: this
//! crate is filled in by the BVH issue; for now it re-exports the math it will build on.

pub use beam_math;
