//! The compute ray tracer (`shaders/raytrace.wgsl`, entry point `trace`) over beam-bvh's GPU layout:
//! closest and any hits for batches of rays. CPU twin: [`beam_bvh::FlatBvh::closest_hit`] and
//! [`beam_bvh::FlatBvh::any_hit`].

use crate::Gpu;
use beam_bvh::gpu::GpuBvh;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

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
        let source = crate::shaders::source("raytrace").ok_or("raytrace shader missing")?;
        let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("raytrace"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("raytrace"),
            layout: None,
            module: &module,
            entry_point: Some("trace"),
            compilation_options: Default::default(),
            cache: None,
        });
        // Empty buffers are not allowed: pad with one zeroed element.
        let upload = |label, bytes: &[u8]| {
            let padded;
            let contents = if bytes.is_empty() {
                padded = vec![0u8; 64];
                &padded[..]
            } else {
                bytes
            };
            gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let nodes = upload("nodes", bytemuck::cast_slice(&bvh.nodes));
        let triangles = upload("triangles", bytemuck::cast_slice(&bvh.triangles));
        Ok(Self { pipeline, nodes, triangles })
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
        let device = &gpu.device;
        let ray_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("rays"),
            contents: bytemuck::cast_slice(rays),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (rays.len() * size_of::<GpuHit>()) as u64;
        let hits = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hits"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("raytrace"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.nodes.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: self.triangles.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: ray_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: hits.as_entire_binding() },
            ],
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("raytrace") });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(groups as u32, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&hits, 0, &readback, 0, size);
        gpu.queue.submit([encoder.finish()]);
        let slice = readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| format!("GPU wait failed: {e}"))?;
        let data = slice.get_mapped_range().map_err(|e| format!("GPU readback failed: {e:?}"))?;
        let out = bytemuck::cast_slice(&data).to_vec();
        drop(data);
        readback.unmap();
        Ok(out)
    }
}
