//! The compute ray tracer (`shaders/raytrace.wgsl`, entry point `trace`) over beam-bvh's GPU layout:
//! closest and any hits for batches of rays. CPU twin: [`beam_bvh::FlatBvh::closest_hit`] and
//! [`beam_bvh::FlatBvh::any_hit`].

use crate::buffers::{buffer_entry, compute_pipeline, encode_pass_timed, max_binding, output, storage};
use crate::interface::{MISS, RAY_ANY, RAY_CLOSEST, WORKGROUP_SIZE};
use crate::timestamps::{PassTimer, read_back_timed};
use crate::{Gpu, GpuError};
use beam_bvh::Hit;
use beam_bvh::gpu::GpuBvh;
use beam_math::Ray;
use beam_scene::scene::Scene;
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

/// A ray for the GPU.
///
/// WGSL twin: `GpuRay` in `shaders/raytrace.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuRay {
    /// Origin.
    pub origin: [f32; 3],
    /// Largest `t` searched.
    pub t_max: f32,
    /// Direction (not necessarily unit; `t` is in its units).
    pub direction: [f32; 3],
    /// [`RAY_CLOSEST`] or [`RAY_ANY`].
    pub kind: u32,
}

const _: () = assert!(size_of::<GpuRay>() == 32);

impl GpuRay {
    /// A closest-hit query of `ray`, searched to any distance.
    #[must_use]
    pub fn closest(ray: &Ray) -> Self {
        Self { origin: ray.origin.to_array(), t_max: 3.0e38, direction: ray.direction.to_array(), kind: RAY_CLOSEST }
    }

    /// An any-hit query of `ray` before `t_max` (a shadow ray).
    #[must_use]
    pub fn any(ray: &Ray, t_max: f32) -> Self {
        Self { origin: ray.origin.to_array(), t_max, direction: ray.direction.to_array(), kind: RAY_ANY }
    }
}

/// A ray's result.
///
/// WGSL twin: `GpuHit` in `shaders/lib/trace.wgsl` (layouts compared in [`crate::interface`]).
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
    /// `prim` of a miss ([`crate::interface::MISS`]).
    pub const MISS: u32 = MISS;
}

/// Upload `bvh`'s nodes and triangles (bindings 0 and 1 of the shaders that traverse it); each must
/// fit one storage binding of `gpu` ([`GpuError::SceneTooLarge`]).
pub(crate) fn upload_bvh(gpu: &Gpu, bvh: &GpuBvh) -> Result<(wgpu::Buffer, wgpu::Buffer), GpuError> {
    let max = max_binding(gpu);
    for (what, bytes) in [("nodes", size_of_val(bvh.nodes())), ("triangles", size_of_val(bvh.triangles()))] {
        if bytes as u64 > max {
            return Err(GpuError::SceneTooLarge { what, bytes: bytes as u64, max });
        }
    }
    let nodes = storage(gpu, "nodes", bvh.nodes(), wgpu::BufferUsages::empty());
    let triangles = storage(gpu, "triangles", bvh.triangles(), wgpu::BufferUsages::empty());
    Ok((nodes, triangles))
}

/// `rays`' closest hits as beam-bvh [`Hit`]s from the tracer's `hits` of them: the tracer reports
/// the triangle and `t`, the barycentric weights of the hit point follow on the host.
#[must_use]
pub fn closest_of(scene: &Scene, rays: &[Ray], hits: Vec<GpuHit>) -> Vec<Option<Hit>> {
    hits.into_par_iter()
        .zip(rays)
        .map(|(h, ray)| {
            (h.prim != GpuHit::MISS).then_some(())?;
            let tri = scene.triangles.get(h.prim as usize)?;
            Some(Hit::on(tri, h.prim, ray, h.t))
        })
        .collect()
}

/// Whether each any-hit ray was occluded: its `t` is 1 when it is, 0 otherwise (`trace_ray`).
#[must_use]
pub fn occluded_of(hits: &[GpuHit]) -> Vec<bool> {
    hits.par_iter().map(|h| h.t == 1.0).collect()
}

/// The compiled pipeline with a BVH uploaded.
pub struct RayTracer {
    pipeline: wgpu::ComputePipeline,
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
}

impl RayTracer {
    /// Compile `raytrace.wgsl` and upload `bvh`; its nodes and its triangles must each fit one
    /// storage binding of `gpu` ([`GpuError::SceneTooLarge`]).
    pub fn new(gpu: &Gpu, bvh: &GpuBvh) -> Result<Self, GpuError> {
        let (nodes, triangles) = upload_bvh(gpu, bvh)?;
        let pipeline = compute_pipeline(gpu, "raytrace", "trace")?;
        Ok(Self { pipeline, nodes, triangles })
    }

    /// The uploaded node and triangle buffers (bindings 0 and 1 of `raytrace.wgsl`).
    #[must_use]
    pub fn buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.nodes, &self.triangles)
    }

    /// Rays of one dispatch on `gpu`: its rays (32 bytes each) within one storage binding, at most
    /// 65,535 workgroups (`trace` reads only `id.x`).
    #[must_use]
    pub fn max_rays(gpu: &Gpu) -> usize {
        let by_binding = max_binding(gpu) / size_of::<GpuRay>() as u64;
        (by_binding.min(65_535 * u64::from(WORKGROUP_SIZE)) as usize).max(1)
    }

    /// Trace `rays`; one result each, in dispatches of at most [`max_rays`](Self::max_rays).
    pub fn trace(&self, gpu: &Gpu, rays: &[GpuRay]) -> Result<Vec<GpuHit>, GpuError> {
        Ok(self.trace_timed(gpu, rays, false)?.0)
    }

    /// [`trace`](Self::trace), and where `timed` and the device has timestamp queries, the
    /// device's seconds in the dispatches.
    pub fn trace_timed(&self, gpu: &Gpu, rays: &[GpuRay], timed: bool) -> Result<(Vec<GpuHit>, Option<f64>), GpuError> {
        let mut out: Vec<GpuHit> = Vec::new();
        let mut seconds: Option<f64> = None;
        for (k, chunk) in rays.chunks(Self::max_rays(gpu)).enumerate() {
            let (hits, s) = self.trace_dispatch(gpu, chunk, timed)?;
            if let Some(s) = s {
                *seconds.get_or_insert(0.0) += s;
            }
            // A miss at t = −1 (of a ray searched from t = 0 on): the traversal's stack overflowed
            // (lib/trace.wgsl), which GpuBvh::new rules out.
            let overflow = |(h, r): (&GpuHit, &GpuRay)| h.prim == MISS && h.t < 0.0 && r.t_max >= 0.0;
            if let Some(i) = hits.par_iter().zip(chunk).position_any(overflow) {
                return Err(GpuError::StackOverflow { ray: k * Self::max_rays(gpu) + i });
            }
            // One dispatch (the common case) hands its hits back as they were read.
            if out.is_empty() {
                out = hits;
            } else {
                out.extend(hits);
            }
        }
        Ok((out, seconds))
    }

    /// One dispatch over `rays` (at most [`max_rays`](Self::max_rays)), timed where `timed`.
    fn trace_dispatch(&self, gpu: &Gpu, rays: &[GpuRay], timed: bool) -> Result<(Vec<GpuHit>, Option<f64>), GpuError> {
        let ray_buffer = storage(gpu, "rays", rays, wgpu::BufferUsages::empty());
        let size = (rays.len() * size_of::<GpuHit>()) as u64;
        let hits = output(gpu, "hits", size);
        let entries = [
            buffer_entry(0, &self.nodes),
            buffer_entry(1, &self.triangles),
            buffer_entry(2, &ray_buffer),
            buffer_entry(3, &hits),
        ];
        let timer = if timed { PassTimer::new(gpu, 1) } else { None };
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let timestamps = timer.as_ref().map(|t| t.compute(0));
        encode_pass_timed(gpu, &mut encoder, &self.pipeline, rays.len() as u32, &entries, timestamps);
        read_back_timed(gpu, encoder, &hits, size, timer.as_ref())
    }
}
