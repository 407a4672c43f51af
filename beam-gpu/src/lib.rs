//! # beam-gpu
//!
//! wgpu + naga pipelines mirroring beam-cpu: headless device set-up, WGSL shaders validated by naga
//! and translatable to SPIR-V, GLSL, MSL and HLSL, and a compute ray tracer over beam-bvh's GPU
//! layout. Every entry point has a CPU twin that the conformance suite compares it with.

pub mod device;
pub mod raytrace;
pub mod shaders;

pub use beam_math;
pub use device::Gpu;
