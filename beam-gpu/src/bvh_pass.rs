//! What the shadow beams and the eye beams share: a compute pipeline over a BVH on the device
//! (bindings 0 and 1, uploaded or a ray tracer's), and each invocation's budget of loop iterations.

use crate::buffers::{buffer_entry, compute_pipeline};
use crate::raytrace::{RayTracer, upload_bvh};
use crate::{Gpu, GpuError};
use beam_bvh::gpu::GpuBvh;

/// Loop iterations an invocation runs on a software device (Mesa's lavapipe, CI's): it ends every
/// loop of a SIMD group of 8 invocations for good once they together have run 65,535 iterations
/// (the shaders count every iteration and 2 for each entry into a loop, as llvmpipe does). A
/// group's count lies between its largest lane's and the sum of its lanes'; where the cap cuts a
/// traversal short anyway, the shader sees it (the loop ended without its own test) and answers
/// `None`, so the cap costs work done again on the host, never a wrong answer.
pub const SOFTWARE_BUDGET: u32 = 8_192;

/// Loop iterations an invocation runs on a hardware device: enough for every beam of the shared
/// scenes, few enough that a pathological one cannot stall the device for long.
pub const HARDWARE_BUDGET: u32 = 1 << 20;

/// The budget of an invocation on `gpu`: [`SOFTWARE_BUDGET`] or [`HARDWARE_BUDGET`].
#[must_use]
pub(crate) fn default_budget(gpu: &Gpu) -> u32 {
    if gpu.is_software() { SOFTWARE_BUDGET } else { HARDWARE_BUDGET }
}

/// A compiled entry point over a BVH on the device, with its invocations' budget.
pub(crate) struct BvhPass {
    pub(crate) pipeline: wgpu::ComputePipeline,
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    pub(crate) budget: u32,
}

impl BvhPass {
    /// Compile `entry` of `shader` and upload `bvh` (each of its buffers within one storage
    /// binding, [`GpuError::SceneTooLarge`]).
    pub(crate) fn new(gpu: &Gpu, (shader, entry): (&str, &str), bvh: &GpuBvh) -> Result<Self, GpuError> {
        let (nodes, triangles) = upload_bvh(gpu, bvh)?;
        Self::over(gpu, (shader, entry), nodes, triangles)
    }

    /// Compile `entry` of `shader` over the BVH `tracer` uploaded (its buffers shared).
    pub(crate) fn sharing(gpu: &Gpu, (shader, entry): (&str, &str), tracer: &RayTracer) -> Result<Self, GpuError> {
        let (nodes, triangles) = tracer.buffers();
        Self::over(gpu, (shader, entry), nodes.clone(), triangles.clone())
    }

    /// The same pipeline and budget over another BVH (no recompilation).
    pub(crate) fn with_bvh(&self, gpu: &Gpu, bvh: &GpuBvh) -> Result<Self, GpuError> {
        let (nodes, triangles) = upload_bvh(gpu, bvh)?;
        Ok(Self { pipeline: self.pipeline.clone(), nodes, triangles, budget: self.budget })
    }

    /// `entry` of `shader` over the same BVH, with the same budget.
    pub(crate) fn with_entry(self, gpu: &Gpu, entry: (&str, &str)) -> Result<Self, GpuError> {
        Ok(Self { pipeline: compute_pipeline(gpu, entry.0, entry.1)?, ..self })
    }

    fn over(
        gpu: &Gpu,
        (shader, entry): (&str, &str),
        nodes: wgpu::Buffer,
        triangles: wgpu::Buffer,
    ) -> Result<Self, GpuError> {
        let pipeline = compute_pipeline(gpu, shader, entry)?;
        Ok(Self { pipeline, nodes, triangles, budget: default_budget(gpu) })
    }

    /// Bindings 0 and 1: the BVH's nodes and triangles.
    pub(crate) fn bvh_entries(&self) -> [wgpu::BindGroupEntry<'_>; 2] {
        [buffer_entry(0, &self.nodes), buffer_entry(1, &self.triangles)]
    }
}
