//! Exact soft shadows on the GPU (`shaders/shadow_beam.wgsl`, entry points `visible_light` and
//! `visible_light_together`, [`Walk`]): one shadow beam per (shade point, light polygon) query, traversed through beam-bvh's GPU layout by
//! its frustum, split exactly at triangle edges with the quad rules of 001 §3.2
//! (`shaders/lib/quad.wgsl`, twin of [`beam_math::polybeam::Quad::split`]), and its unoccluded
//! pieces integrated by Lambert's formula. CPU twin: `beam_cpu::render::light_seen`.
//!
//! A beam holds at most [`MAX_PIECES`] pieces and runs at most its budget of loop iterations
//! ([`ShadowBeams::budget`]); past either it answers `None` (counted, and traced again by the
//! caller on its own path), never a wrong value.
//!
//! [`ShadowBeams::answers_timed`] also measures the dispatches' own time on the device by
//! timestamp queries (`PassTimer`), for benchmarks.

use crate::buffers::{buffer_entry, checked, encode_pass_timed, max_binding, output, storage, uniform};
use crate::bvh_pass::BvhPass;
use crate::interface::{QUERY_CLIP_ABOVE, SHADOW_DONE};
use crate::raytrace::RayTracer;
use crate::timestamps::{PassTimer, read_back_timed};
use crate::{Gpu, GpuError};
use beam_bvh::gpu::GpuBvh;
use beam_render::queries::{LightPolygon, LightQuery, LightSeen, MAX_LIGHT_CORNERS};
use bytemuck::{Pod, Zeroable};

pub use crate::bvh_pass::{HARDWARE_BUDGET, SOFTWARE_BUDGET};
pub use crate::interface::MAX_PIECES;

/// A shadow-beam query for the GPU.
///
/// WGSL twin: `LightQuery` in `shaders/shadow_beam.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLightQuery {
    /// The shade point.
    pub p: [f32; 3],
    /// Index of the light polygon.
    pub light: u32,
    /// Unit normal at the point.
    pub n: [f32; 3],
    /// [`QUERY_CLIP_ABOVE`] or 0.
    pub flags: u32,
}

impl GpuLightQuery {
    /// `q` for the shader.
    #[must_use]
    pub fn new(q: &LightQuery) -> Self {
        let flags = if q.clip_above { QUERY_CLIP_ABOVE } else { 0 };
        Self { p: q.p.to_array(), light: q.light, n: q.n.to_array(), flags }
    }
}

/// A light polygon for the GPU.
///
/// WGSL twin: `LightPolygon` in `shaders/shadow_beam.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLightPolygon {
    /// Corners (`w` unused).
    pub corners: [[f32; 4]; MAX_LIGHT_CORNERS],
    /// Unit normal of the lit side.
    pub normal: [f32; 3],
    /// Number of corners.
    pub count: u32,
}

impl GpuLightPolygon {
    /// `l` for the shader.
    #[must_use]
    pub fn new(l: &LightPolygon) -> Self {
        let corners = l.corners.map(|c| c.extend(0.0).to_array());
        Self { corners, normal: l.normal.to_array(), count: l.count }
    }
}

/// A shadow beam's answer.
///
/// WGSL twin: `LightSeen` in `shaders/shadow_beam.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLightSeen {
    /// Irradiance per unit radiance of the unoccluded pieces.
    pub irradiance: f32,
    /// Unoccluded share of the beam's cross-section.
    pub fraction: f32,
    /// [`SHADOW_DONE`], or why the beam stopped short ([`crate::interface::SHADOW_PIECES`],
    /// [`crate::interface::SHADOW_BUDGET`], [`crate::interface::SHADOW_CUT`]).
    pub status: u32,
    /// Loop iterations the beam ran.
    pub work: u32,
}

impl GpuLightSeen {
    /// The answer, `None` for a beam past the limits.
    #[must_use]
    pub fn seen(&self) -> Option<LightSeen> {
        (self.status == SHADOW_DONE).then_some(LightSeen { irradiance: self.irradiance, fraction: self.fraction })
    }
}

/// The parameters of one dispatch.
///
/// WGSL twin: `ShadowParams` in `shaders/shadow_beam.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ShadowParams {
    /// Queries of the dispatch.
    pub queries: u32,
    /// Loop iterations a beam may run.
    pub budget: u32,
    /// Index of the dispatch's first query in the bound buffers.
    pub first: u32,
    /// Padding.
    pub pad: u32,
}

const _: () = assert!(
    size_of::<GpuLightQuery>() == 32
        && size_of::<GpuLightPolygon>() == 144
        && size_of::<GpuLightSeen>() == 16
        && size_of::<ShadowParams>() == 16
);

/// Queries per dispatch (a dispatch's buffers stay small, and a workgroup count under 65,535).
const CHUNK: usize = 1 << 18;

/// The compiled pipeline, over a BVH already on the device.
pub struct ShadowBeams {
    pass: BvhPass,
}

/// How a workgroup's beams walk the BVH.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Walk {
    /// Each beam down its own path (entry point `visible_light`): the default, measured on a real
    /// GPU (docs/benchmarks.md).
    #[default]
    Alone,
    /// The group's beams together, a node at a time, each testing the nodes it would test alone
    /// (entry point `visible_light_together`): the same answers wherever both finish, the nodes
    /// and triangles read once for the group. Its loop holds barriers, which Mesa llvmpipe's loop
    /// cap makes unsafe for long walks, so the group's iterations summed over its beams end it at
    /// 5 beams' budgets, on any device; a beam's own budget counts the group's steps. Not yet
    /// timed on a real GPU: `beam bench softshadow --backend gpu` times both walks.
    Together,
}

impl Walk {
    fn entry(self) -> (&'static str, &'static str) {
        match self {
            Self::Alone => ("shadow_beam", "visible_light"),
            Self::Together => ("shadow_beam", "visible_light_together"),
        }
    }
}

impl ShadowBeams {
    /// Compile `shadow_beam.wgsl` and upload `bvh` (each of its buffers within one storage binding,
    /// [`GpuError::SceneTooLarge`]); the beams walk alone ([`Self::walking`]).
    pub fn new(gpu: &Gpu, bvh: &GpuBvh) -> Result<Self, GpuError> {
        Ok(Self { pass: BvhPass::new(gpu, Walk::Alone.entry(), bvh)? })
    }

    /// Compile `shadow_beam.wgsl` over the BVH `tracer` uploaded (its buffers shared).
    pub fn sharing(gpu: &Gpu, tracer: &RayTracer) -> Result<Self, GpuError> {
        Ok(Self { pass: BvhPass::sharing(gpu, Walk::Alone.entry(), tracer)? })
    }

    /// These beams walking the BVH as `walk` says (its entry point compiled; the BVH and budget
    /// kept).
    pub fn walking(self, gpu: &Gpu, walk: Walk) -> Result<Self, GpuError> {
        Ok(Self { pass: self.pass.with_entry(gpu, walk.entry())? })
    }

    /// The same pipeline over another BVH (no recompilation).
    pub fn with_bvh(&self, gpu: &Gpu, bvh: &GpuBvh) -> Result<Self, GpuError> {
        Ok(Self { pass: self.pass.with_bvh(gpu, bvh)? })
    }

    /// These beams with a budget of `budget` loop iterations each (tests force the overflow path).
    #[must_use]
    pub fn with_budget(mut self, budget: u32) -> Self {
        self.pass.budget = budget;
        self
    }

    /// Loop iterations a beam may run before it answers `None`.
    #[must_use]
    pub fn budget(&self) -> u32 {
        self.pass.budget
    }

    /// Encode the beams of `count` queries of `queries` (from `first` on) against `lights` into
    /// `seen` ([`GpuLightSeen`] each, at the query's index), on buffers the caller owns: nothing is
    /// read back (an engine keeps the answers on the device).
    #[allow(
        clippy::too_many_arguments,
        reason = "the device, the encoder, three buffers and the range of one dispatch"
    )]
    pub fn encode(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        lights: &wgpu::Buffer,
        queries: &wgpu::Buffer,
        seen: &wgpu::Buffer,
        first: u32,
        count: u32,
    ) {
        self.encode_timed(gpu, encoder, (lights, queries, seen), (first, count), None);
    }

    /// [`Self::encode`], the pass's beginning and end written to `timer`'s queries of pass 0.
    fn encode_timed(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        (lights, queries, seen): (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
        (first, count): (u32, u32),
        timer: Option<&PassTimer>,
    ) {
        let params = ShadowParams { queries: count, budget: self.pass.budget, first, pad: 0 };
        let params = uniform(gpu, "shadow params", bytemuck::bytes_of(&params));
        let [nodes, triangles] = self.pass.bvh_entries();
        let entries = [
            nodes,
            triangles,
            buffer_entry(2, &params),
            buffer_entry(3, lights),
            buffer_entry(4, queries),
            buffer_entry(5, seen),
        ];
        let timestamps = timer.map(|t| t.compute(0));
        encode_pass_timed(gpu, encoder, &self.pass.pipeline, count, &entries, timestamps);
    }

    /// The answer to each query (`None` past the limits), in dispatches of at most 2¹⁸ queries.
    pub fn visibility(
        &self,
        gpu: &Gpu,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<Option<LightSeen>>, GpuError> {
        Ok(self.answers(gpu, lights, queries)?.iter().map(GpuLightSeen::seen).collect())
    }

    /// The shader's answers as they are (with their status and work).
    pub fn answers(
        &self,
        gpu: &Gpu,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<GpuLightSeen>, GpuError> {
        Ok(self.run(gpu, lights, queries, false)?.0)
    }

    /// [`Self::answers`], and the device's own seconds in the beams' dispatches, summed, by
    /// timestamp queries at each pass's beginning and end (`PassTimer`): the time of the shader
    /// alone, without the uploads, the readbacks or the host's waits. `None` where the device has
    /// no timestamp queries (`wgpu::Features::TIMESTAMP_QUERY`); `Some(0.0)` for no queries.
    pub fn answers_timed(
        &self,
        gpu: &Gpu,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<(Vec<GpuLightSeen>, Option<f64>), GpuError> {
        self.run(gpu, lights, queries, true)
    }

    /// The answers in dispatches of at most 2¹⁸ queries; with `timed`, and where the device has
    /// timestamp queries, the dispatches' seconds on the device.
    fn run(
        &self,
        gpu: &Gpu,
        lights: &[LightPolygon],
        queries: &[LightQuery],
        timed: bool,
    ) -> Result<(Vec<GpuLightSeen>, Option<f64>), GpuError> {
        if let Some(q) = queries.iter().find(|q| q.light as usize >= lights.len()) {
            return Err(GpuError::NoSuchLight { light: q.light, lights: lights.len() });
        }
        let polygons: Vec<GpuLightPolygon> = lights.iter().map(GpuLightPolygon::new).collect();
        let chunk = CHUNK.min((max_binding(gpu) / size_of::<GpuLightQuery>() as u64) as usize).max(1);
        let timed = timed && gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        checked(gpu, || {
            let lights = storage(gpu, "light polygons", &polygons, wgpu::BufferUsages::empty());
            let mut out = Vec::with_capacity(queries.len());
            let mut seconds = timed.then_some(0.0);
            for part in queries.chunks(chunk) {
                let gpu_queries: Vec<GpuLightQuery> = part.iter().map(GpuLightQuery::new).collect();
                let queries = storage(gpu, "light queries", &gpu_queries, wgpu::BufferUsages::empty());
                let size = (part.len() * size_of::<GpuLightSeen>()) as u64;
                let seen = output(gpu, "light seen", size);
                let timer = if timed { PassTimer::new(gpu, 1) } else { None };
                let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
                let n = part.len() as u32;
                self.encode_timed(gpu, &mut encoder, (&lights, &queries, &seen), (0, n), timer.as_ref());
                let (answers, pass) = read_back_timed::<GpuLightSeen>(gpu, encoder, &seen, size, timer.as_ref())?;
                out.extend(answers);
                seconds = seconds.map(|s| s + pass.unwrap_or(0.0));
            }
            Ok((out, seconds))
        })
    }
}
