//! # beam-cpu
//!
//! Host side of beam: scenes, cameras, materials, lights and the CPU renderers. Work in progress:
//! the renderers arrive with the rendering issues.

pub use beam_math;
