//! Shading on the GPU (`shaders/raytrace.wgsl`, entry point `shade`): diffuse, glossy and emissive
//! points lit by point lights, shadow rays traced through the GPU BVH, plus the caustic irradiance
//! maps of the nonlinear renderer. CPU twin: [`beam_cpu::render::shade_point`] on scenes whose
//! lights are all point lights (area lights' exact soft shadows by 001 beams stay on the CPU).

use crate::Gpu;
use crate::buffers::{checked, compute_pipeline, output, read_back, storage};
use crate::raytrace::RayTracer;
use beam_cpu::nonlinear::ShadePoint;
use beam_cpu::render::{IrradianceMap, shading_eps};
use beam_cpu::scene::{Light, Material, Scene};
use beam_math::glam::Vec3;
use bytemuck::{Pod, Zeroable};

/// A point to shade.
///
/// Keep in sync with the WGSL twin `ShadeInput` in `shaders/raytrace.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ShadeInput {
    /// The point.
    pub p: [f32; 3],
    /// Its scene triangle.
    pub prim: u32,
    /// Unit direction of the arriving ray.
    pub d: [f32; 3],
    /// Padding.
    pub pad: u32,
}

/// What shading needs of a scene triangle.
///
/// Keep in sync with the WGSL twin `PrimShading` in `shaders/raytrace.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PrimShading {
    /// Unit geometric normal.
    pub normal: [f32; 3],
    /// 0: diffuse or glossy (`color` the albedo); 1: emissive (`color` the radiance).
    pub kind: u32,
    /// Albedo or radiance.
    pub color: [f32; 3],
    /// Its plane in the caustic irradiance maps, −1 for none.
    pub plane: i32,
}

/// A point light.
///
/// Keep in sync with the WGSL twin `PointLight` in `shaders/raytrace.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuPointLight {
    /// Position.
    pub position: [f32; 3],
    /// Padding.
    pub pad: u32,
    /// Radiant intensity.
    pub intensity: [f32; 3],
    /// Padding.
    pub pad2: u32,
}

/// One plane of the caustic irradiance maps.
///
/// Keep in sync with the WGSL twin `CausticPlane` in `shaders/raytrace.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CausticPlane {
    /// Texel-centre origin.
    pub origin: [f32; 3],
    /// Its first texel in the flux buffer.
    pub offset: u32,
    /// First axis, scaled to texels.
    pub axis_u: [f32; 3],
    /// Texels along it.
    pub width: u32,
    /// Second axis, scaled to texels.
    pub axis_v: [f32; 3],
    /// Texels along it.
    pub height: u32,
}

/// Uniforms of the shading pass.
///
/// Keep in sync with the WGSL twin `ShadeParams` in `shaders/raytrace.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ShadeParams {
    /// Offset of shadow-ray origins off the surface.
    pub eps: f32,
    /// `1 / texel²` of the irradiance maps.
    pub inv_texel_area: f32,
    /// Point lights.
    pub lights: u32,
    /// Points to shade.
    pub points: u32,
}

const _: () = assert!(
    size_of::<ShadeInput>() == 32
        && size_of::<PrimShading>() == 32
        && size_of::<GpuPointLight>() == 32
        && size_of::<CausticPlane>() == 48
        && size_of::<ShadeParams>() == 16
);

/// The shading pass with a scene's triangles and lights uploaded.
pub struct PointShader {
    pipeline: wgpu::ComputePipeline,
    prims: Vec<PrimShading>,
    lights: wgpu::Buffer,
    light_count: u32,
    eps: f32,
}

impl PointShader {
    /// The pass for `scene`; `None` when it has an area light (shaded on the CPU).
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Option<Self>, String> {
        let mut lights = Vec::new();
        for light in &scene.lights {
            match *light {
                Light::Point { position, intensity } => lights.push(GpuPointLight {
                    position: position.to_array(),
                    pad: 0,
                    intensity: intensity.to_array(),
                    pad2: 0,
                }),
                _ => return Ok(None),
            }
        }
        let prims: Vec<PrimShading> = (0..scene.triangles.len() as u32)
            .map(|i| {
                let (kind, color) = match scene.material(i) {
                    Material::Emissive { radiance } => (1, radiance),
                    Material::Diffuse { albedo } | Material::Glossy { albedo, .. } => (0, albedo),
                    _ => (2, Vec3::ZERO),
                };
                PrimShading { normal: scene.normal(i).to_array(), kind, color: color.to_array(), plane: -1 }
            })
            .collect();
        Ok(Some(Self {
            pipeline: compute_pipeline(gpu, "raytrace", "shade")?,
            prims,
            lights: storage(gpu, "point lights", bytemuck::cast_slice(&lights), wgpu::BufferUsages::empty()),
            light_count: lights.len() as u32,
            eps: shading_eps(scene),
        }))
    }

    /// True when the pass shades points of triangle `prim` (diffuse, glossy, emissive).
    #[must_use]
    pub fn shades(scene: &Scene, prim: u32) -> bool {
        matches!(scene.material(prim), Material::Diffuse { .. } | Material::Glossy { .. } | Material::Emissive { .. })
    }

    /// The radiance of `points` (all of triangles the pass [`shades`](Self::shades)), shadow rays
    /// through `tracer`'s BVH, with the irradiance of `caustics`.
    pub fn shade(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Result<Vec<Vec3>, String> {
        if points.is_empty() {
            return Ok(Vec::new());
        }
        let mut planes = Vec::new();
        let mut flux: Vec<[f32; 4]> = Vec::new();
        let mut prims = self.prims.clone();
        if let Some(map) = caustics {
            // Which plane each triangle's points read.
            for (i, p) in prims.iter_mut().enumerate() {
                p.plane = map.plane_of(i as u32).map_or(-1, |k| k as i32);
            }
            for (origin, axes, size, texels) in map.grids() {
                planes.push(CausticPlane {
                    origin: origin.to_array(),
                    offset: flux.len() as u32,
                    axis_u: axes[0].to_array(),
                    width: size[0],
                    axis_v: axes[1].to_array(),
                    height: size[1],
                });
                flux.extend(texels.iter().map(|f| [f.x, f.y, f.z, 0.0]));
            }
        }
        let inputs: Vec<ShadeInput> =
            points.iter().map(|s| ShadeInput { p: s.p.to_array(), prim: s.prim, d: s.d.to_array(), pad: 0 }).collect();
        let texel = caustics.map_or(1.0, |m| m.texel);
        let params = ShadeParams {
            eps: self.eps,
            inv_texel_area: 1.0 / (texel * texel),
            lights: self.light_count,
            points: points.len() as u32,
        };
        checked(gpu, || {
            let uniform = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("shade params"),
                size: size_of::<ShadeParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            gpu.queue.write_buffer(&uniform, 0, bytemuck::bytes_of(&params));
            let input = storage(gpu, "shade points", bytemuck::cast_slice(&inputs), wgpu::BufferUsages::empty());
            let prim_buffer = storage(gpu, "prim shading", bytemuck::cast_slice(&prims), wgpu::BufferUsages::empty());
            let plane_buffer =
                storage(gpu, "caustic planes", bytemuck::cast_slice(&planes), wgpu::BufferUsages::empty());
            let flux_buffer = storage(gpu, "caustic flux", bytemuck::cast_slice(&flux), wgpu::BufferUsages::empty());
            let size = (points.len() * 16) as u64;
            let out = output(gpu, "radiance", size);
            let (nodes, triangles) = tracer.buffers();
            let entries: Vec<wgpu::BindGroupEntry<'_>> = [
                (0, nodes),
                (1, triangles),
                (4, &uniform),
                (5, &input),
                (6, &prim_buffer),
                (7, &self.lights),
                (8, &plane_buffer),
                (9, &flux_buffer),
                (10, &out),
            ]
            .into_iter()
            .map(|(binding, b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() })
            .collect();
            let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shade"),
                layout: &self.pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &bind, &[]);
                let groups = points.len().div_ceil(64) as u32;
                pass.dispatch_workgroups(groups.min(65_535), groups.div_ceil(65_535), 1);
            }
            let radiance: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&read_back(gpu, encoder, &out, size)?);
            Ok(radiance.iter().map(|r| Vec3::new(r[0], r[1], r[2])).collect())
        })
    }
}
