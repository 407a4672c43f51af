//! # beam-gpu
//!
//! wgpu + naga pipelines mirroring beam-cpu: headless device set-up, WGSL shaders validated by naga
//! and translatable to SPIR-V, GLSL, MSL and HLSL (their constants shared with Rust from one table,
//! [`interface`], and their structs' layouts checked against the Rust twins), a compute ray tracer over beam-bvh's GPU
//! layout, and the nonlinear beam pipeline of 000 (bounding triangles in a vertex stage, per-texel
//! rays in a fragment stage, per-level atlases, the composite), and the gather of the glossy light
//! volumes of 002. Every entry point has a CPU twin that the conformance suite compares it with.
//! It is a backend of `beam-render`: it implements that crate's renderer traits (ray queries, the
//! nonlinear method's `BeamRenderer`) and shares its host side of the beam tree and the glossy light
//! volumes with beam-cpu. Errors are [`GpuError`]s; behind the renderer's traits they become
//! [`BackendError`](beam_render::BackendError)s.
//!
//! Trace camera rays on the GPU (here a device beam opens; an engine hands its own
//! `wgpu::Device` and `Queue` to [`Gpu`] instead, see `examples/engine_device.rs`):
//!
//! ```
//! use beam_bvh::gpu::GpuBvh;
//! use beam_gpu::raytrace::{GpuRay, RayTracer};
//!
//! let gpu = match beam_gpu::Gpu::new() {
//!     Ok(gpu) => gpu,
//!     // No adapter: nothing to show, unless one is required (CI sets BEAM_REQUIRE_GPU=1).
//!     Err(e) if std::env::var("BEAM_REQUIRE_GPU").as_deref() == Ok("1") => panic!("{e}"),
//!     Err(_) => return,
//! };
//! let scene = beam_scene::scene::builtin("cornell").unwrap();
//! let tracer = RayTracer::new(&gpu, &GpuBvh::new(&scene.bvh, &scene.triangles).unwrap()).unwrap();
//! let camera = scene.camera.with_size(16, 16);
//! let frame = camera.frame();
//! let rays: Vec<GpuRay> = (0..256).map(|i| GpuRay::closest(&camera.pixel_ray(&frame, i))).collect();
//! let hits = tracer.trace(&gpu, &rays).unwrap();
//! assert_eq!(hits.len(), 256);
//! ```

pub mod buffers;
mod bvh_pass;
pub mod checks;
mod device;
mod error;
pub mod eye_beam;
pub mod gbuffer;
pub mod glossy;
pub mod interface;
pub mod nonlinear;
mod pool;
pub mod queries;
pub mod raytrace;
mod scratch;
pub mod shade;
pub mod shaders;
pub mod shadow_beam;
mod staging;
mod texels;
mod timestamps;

pub use beam_math;
pub use device::{Gpu, Traffic};
pub use error::GpuError;
