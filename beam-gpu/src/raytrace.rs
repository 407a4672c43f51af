//! The compute ray tracer (`shaders/raytrace.wgsl`, entry point `trace`) over beam-bvh's GPU layout:
//! closest and any hits for batches of rays. CPU twin: [`beam_bvh::FlatBvh::closest_hit`] and
//! [`beam_bvh::FlatBvh::any_hit`].

use crate::Gpu;
use crate::buffers::{compute_pipeline, dispatch, output, read_back, storage};
use beam_bvh::gpu::GpuBvh;
use bytemuck::{Pod, Zeroable};

/// A ray for the GPU.
///
/// Keep in sync with the WGSL twin `GpuRay` in `shaders/raytrace.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuRay {
    /// Origin.
    pub origin: [f32; 3],
    /// Largest `t` searched.
    pub t_max: f32,
    /// Direction (not necessarily unit; `t` is in its units).
    pub direction: [f32; 3],
    /// 0: closest hit; 1: any hit.
    pub kind: u32,
}

const _: () = assert!(size_of::<GpuRay>() == 32);

/// A ray's result.
///
/// Keep in sync with the WGSL twin `GpuHit` in `shaders/raytrace.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuHit {
    /// Input index of the hit triangle, [`GpuHit::MISS`] on a miss.
    pub prim: u32,
    /// Distance of a closest hit; for an any-hit ray 1 when occluded, else 0.
    pub t: f32,
}

const _: () = assert!(size_of::<GpuHit>() == 8);

impl GpuHit {
    /// `prim` of a miss.
    pub const MISS: u32 = u32::MAX;
}

/// The compiled pipeline with a BVH uploaded.
pub struct RayTracer {
    pipeline: wgpu::ComputePipeline,
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
}

impl RayTracer {
    /// Compile `raytrace.wgsl` and upload `bvh`.
    pub fn new(gpu: &Gpu, bvh: &GpuBvh) -> Result<Self, String> {
        let pipeline = compute_pipeline(gpu, "raytrace", "trace")?;
        let nodes = storage(gpu, "nodes", &bvh.nodes, wgpu::BufferUsages::empty());
        let triangles = storage(gpu, "triangles", &bvh.triangles, wgpu::BufferUsages::empty());
        Ok(Self { pipeline, nodes, triangles })
    }

    /// The uploaded node and triangle buffers (bindings 0 and 1 of `raytrace.wgsl`).
    #[must_use]
    pub fn buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.nodes, &self.triangles)
    }

    /// Trace `rays`; one result each.
    pub fn trace(&self, gpu: &Gpu, rays: &[GpuRay]) -> Result<Vec<GpuHit>, String> {
        if rays.is_empty() {
            return Ok(Vec::new());
        }
        // One dispatch: at most 65,535 workgroups of 64 rays.
        let groups = rays.len().div_ceil(64);
        if groups > 65_535 {
            return Err(format!("{} rays exceed one dispatch (at most {})", rays.len(), 65_535 * 64));
        }
        let ray_buffer = storage(gpu, "rays", rays, wgpu::BufferUsages::empty());
        let size = (rays.len() * size_of::<GpuHit>()) as u64;
        let hits = output(gpu, "hits", size);
        let encoder = dispatch(gpu, &self.pipeline, &[&self.nodes, &self.triangles, &ray_buffer, &hits], groups as u32);
        Ok(bytemuck::pod_collect_to_vec(&read_back(gpu, encoder, &hits, size)?))
    }
}
