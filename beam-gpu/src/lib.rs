//! # beam-gpu
//!
//! wgpu + naga pipelines mirroring beam-cpu: headless device set-up, WGSL shaders validated by naga
//! and translatable to SPIR-V, GLSL, MSL and HLSL (their constants shared with Rust from one table,
//! [`interface`], and their structs' layouts checked against the Rust twins), a compute ray tracer over beam-bvh's GPU
//! layout, and the nonlinear beam pipeline of 000 (bounding triangles in a vertex stage, per-texel
//! rays in a fragment stage, per-level atlases, the composite), and the gather of the glossy light
//! volumes of 002. Every entry point has a CPU twin that the conformance suite compares it with.
//! Errors are [`GpuError`]s; as a backend of the renderer's traits they become `BackendError`s.

pub mod buffers;
pub mod device;
pub mod error;
pub mod glossy;
pub mod interface;
pub mod nonlinear;
pub mod raytrace;
pub mod shade;
pub mod shaders;

pub use beam_math;
pub use device::Gpu;
pub use error::GpuError;
