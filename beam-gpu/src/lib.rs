//! # beam-gpu
//!
//! wgpu + naga pipelines mirroring beam-cpu. Work in progress: the shaders arrive with the GPU issue.

pub use beam_math;
