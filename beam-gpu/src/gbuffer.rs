//! Exact soft shadows for an engine that owns the device: the irradiance of every pixel of its
//! G-buffer (positions and normals in storage buffers) from the scene's area lights, by one exact
//! shadow beam per pixel and light (`shaders/shadow_beam.wgsl`, entry point `gbuffer_irradiance`),
//! written into an `Rgba32Float` storage texture, with nothing read back. CPU twin: the sum over
//! the lights of `radiance × beam_cpu::render::light_seen(…).irradiance` at each pixel.
//!
//! A beam that stops short (past [`crate::shadow_beam::MAX_PIECES`] pieces or the pixel's work
//! budget) adds nothing to its pixel; the pixel's alpha says how many did, and
//! [`GBufferShadows::stopped_short`] how many in all, so that the engine can trace them again.

use crate::buffers::{buffer_entry, encode_pass, output, read_back, storage, uniform, view_entry};
use crate::bvh_pass::BvhPass;
use crate::shadow_beam::GpuLightPolygon;
use crate::{Gpu, GpuError};
use beam_bvh::gpu::GpuBvh;
use beam_math::glam::Vec3;
use beam_render::queries::LightPolygon;
use beam_scene::scene::{Light, Scene};
use bytemuck::{Pod, Zeroable};

/// The parameters of a G-buffer pass.
///
/// WGSL twin: `GBufferParams` in `shaders/shadow_beam.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GBufferParams {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Lights.
    pub lights: u32,
    /// Loop iterations all of a pixel's beams together may run.
    pub budget: u32,
    /// How far a shade point is lifted off its surface along its normal.
    pub offset: f32,
    /// Padding.
    pub pad: [u32; 3],
}

const _: () = assert!(size_of::<GBufferParams>() == 32);

/// An engine's G-buffer: per pixel, row by row, a world-space position `[x, y, z, w]` (`w` 1 where
/// a surface is, 0 elsewhere) and a unit normal `[x, y, z, 0]` facing the viewer, each in a storage
/// buffer of `width × height` 16-byte elements.
pub struct GBuffer<'a> {
    /// Positions.
    pub positions: &'a wgpu::Buffer,
    /// Normals.
    pub normals: &'a wgpu::Buffer,
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

/// `scene`'s area lights as polygons with their emitted radiance (point lights have none).
#[must_use]
pub fn area_lights(scene: &Scene) -> Vec<(LightPolygon, Vec3)> {
    scene
        .lights
        .iter()
        .filter_map(|l| match l {
            Light::Quad { radiance, .. } | Light::Triangle { radiance, .. } => {
                Some((LightPolygon::new(&l.polygon(), l.normal())?, *radiance))
            }
            Light::Point { .. } => None,
        })
        .collect()
}

/// The scene's occluders and area lights on the device, and the pipeline.
pub struct GBufferShadows {
    pass: BvhPass,
    lights: wgpu::Buffer,
    radiance: wgpu::Buffer,
    light_count: u32,
    offset: f32,
    stopped_short: wgpu::Buffer,
}

impl GBufferShadows {
    /// Upload `scene`'s BVH and its area lights (point lights cast no soft shadows and are left to
    /// the engine) and compile the pass. Shade points are lifted off their surfaces by the scene's
    /// shading tolerance.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let lights = area_lights(scene);
        let bvh = GpuBvh::new(&scene.bvh, &scene.triangles)?;
        let offset = beam_render::tolerance::shading_eps(scene);
        Self::from_parts(gpu, &bvh, &lights, offset)
    }

    /// The pass over occluders `bvh` and `lights` (each polygon with its emitted radiance), shade
    /// points lifted by `offset` along their normals.
    pub fn from_parts(gpu: &Gpu, bvh: &GpuBvh, lights: &[(LightPolygon, Vec3)], offset: f32) -> Result<Self, GpuError> {
        let polygons: Vec<GpuLightPolygon> = lights.iter().map(|(l, _)| GpuLightPolygon::new(l)).collect();
        let radiance: Vec<[f32; 4]> = lights.iter().map(|(_, r)| r.extend(0.0).to_array()).collect();
        Ok(Self {
            pass: BvhPass::new(gpu, ("shadow_beam", "gbuffer_irradiance"), bvh)?,
            lights: storage(gpu, "light polygons", &polygons, wgpu::BufferUsages::empty()),
            radiance: storage(gpu, "light radiance", &radiance, wgpu::BufferUsages::empty()),
            light_count: lights.len() as u32,
            offset,
            stopped_short: output(gpu, "beams stopped short", 4),
        })
    }

    /// This pass with a work budget of `budget` loop iterations per pixel (tests force beams to
    /// stop short with a small one).
    #[must_use]
    pub fn with_budget(mut self, budget: u32) -> Self {
        self.pass.budget = budget;
        self
    }

    /// Record the pass into `encoder`: the irradiance of every pixel of `gbuffer` into `target`, a
    /// view of an `Rgba32Float` texture of the G-buffer's size with `STORAGE_BINDING` usage (rgb:
    /// irradiance; a: the pixel's beams that stopped short). The count of those is reset here and
    /// read by [`Self::stopped_short`].
    pub fn encode(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer<'_>,
        target: &wgpu::TextureView,
    ) {
        let params = GBufferParams {
            width: gbuffer.width,
            height: gbuffer.height,
            lights: self.light_count,
            budget: self.pass.budget,
            offset: self.offset,
            pad: [0; 3],
        };
        let params = uniform(gpu, "gbuffer params", bytemuck::bytes_of(&params));
        encoder.clear_buffer(&self.stopped_short, 0, None);
        let [nodes, triangles] = self.pass.bvh_entries();
        let entries = [
            nodes,
            triangles,
            buffer_entry(3, &self.lights),
            buffer_entry(6, &params),
            buffer_entry(7, gbuffer.positions),
            buffer_entry(8, gbuffer.normals),
            buffer_entry(9, &self.radiance),
            view_entry(10, target),
            buffer_entry(11, &self.stopped_short),
        ];
        encode_pass(gpu, encoder, &self.pass.pipeline, gbuffer.width * gbuffer.height, &entries);
    }

    /// Beams of the last submitted pass that stopped short (a wait and a 4-byte readback).
    pub fn stopped_short(&self, gpu: &Gpu) -> Result<u32, GpuError> {
        let encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        Ok(read_back::<u32>(gpu, encoder, &self.stopped_short, 4)?.first().copied().unwrap_or(0))
    }
}
