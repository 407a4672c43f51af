//! The eye's view of a frame on the GPU (`shaders/eye.wgsl`, 000 §7.3): every pixel's primary ray
//! made and traced there. The diffuse, glossy and emissive hits of the crop become shading inputs
//! that stay on the GPU ([`KeptPoints`], shaded and written to the eye's level by the composite);
//! only the mirror and glass hits, from which the host builds the beam tree, are read back. CPU
//! twin: [`Camera::pixel_ray`] and the nearest hit of each ray.

use super::atlas::GpuBeams;
use super::composite::GpuComposite;
use crate::buffers::{checked, compute_pipeline, dispatch, output, read_all, storage, uniform};
use crate::interface::WORKGROUP_SIZE;
use crate::raytrace::RayTracer;
use crate::shade::{PointShader, ShadeInput};
use crate::texels;
use crate::{Gpu, GpuError};
use beam_bvh::Hit;
use beam_math::glam::Vec3;
use beam_math::{Ray, Triangle};
use beam_scene::BackendError;
use beam_scene::nonlinear::{EyeView, ShadePoint, TexelRadiance, eye_by_rays};
use beam_scene::options::{RenderOptions, Shading};
use beam_scene::region::PixelRect;
use beam_scene::scene::{Camera, Scene};
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;
use std::sync::PoisonError;
use std::time::Instant;

/// The camera's frame and one dispatch's pixels.
///
/// WGSL twin: `EyeParams` in `shaders/eye.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct EyeParams {
    /// Eye position.
    pub position: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Unit view direction (of the camera's frame, `Camera::frame`).
    pub forward: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Unit right vector.
    pub right: [f32; 3],
    /// First pixel of the dispatch (row-major).
    pub first: u32,
    /// Unit up vector.
    pub up: [f32; 3],
    /// Pixels of the dispatch.
    pub count: u32,
    /// Half width of the image plane at distance 1.
    pub half_width: f32,
    /// Half height of the image plane at distance 1.
    pub half_height: f32,
    /// Padding.
    pub pad: [u32; 2],
    /// The crop, `[x0, y0, x1, y1]`: only its diffuse, glossy and emissive hits are kept.
    pub crop: [u32; 4],
}

/// A mirror or glass hit of the eye's view, read back for the host.
///
/// WGSL twin: `EyeHit` in `shaders/eye.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct EyeHit {
    /// The pixel (row-major).
    pub pixel: u32,
    /// The scene triangle hit.
    pub prim: u32,
    /// The ray parameter of the hit (the ray from the eye through the pixel's centre on the image
    /// plane at distance 1).
    pub t: f32,
    /// Padding.
    pub pad: u32,
}

/// What one dispatch appended.
///
/// WGSL twin: `EyeCounts` in `shaders/eye.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct EyeCounts {
    /// Shading inputs kept.
    pub kept: u32,
    /// Hits appended for the host.
    pub others: u32,
    /// 1 + the largest pixel whose traversal overflowed its stack, 0 for none.
    pub overflow: u32,
    /// Padding.
    pub pad: u32,
}

const _: () = assert!(size_of::<EyeParams>() == 96 && size_of::<EyeHit>() == 16 && size_of::<EyeCounts>() == 16);

/// The shading inputs one dispatch of the eye's view kept on the GPU.
pub struct KeptPoints {
    /// [`ShadeInput`]s, `count` of them.
    pub inputs: wgpu::Buffer,
    /// The pixel of each.
    pub targets: wgpu::Buffer,
    /// How many.
    pub count: u32,
}

/// The eye's view pass.
pub struct GpuEye {
    pipeline: wgpu::ComputePipeline,
    /// Per scene triangle: 1 where the shading pass shades it.
    plain: wgpu::Buffer,
}

impl GpuEye {
    /// Compile the pass and upload which of `scene`'s triangles the shading pass shades.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let plain: Vec<u32> =
            (0..scene.triangles.len() as u32).map(|p| u32::from(PointShader::shades(scene, p))).collect();
        Ok(Self {
            pipeline: compute_pipeline(gpu, "eye", "eye_view")?,
            plain: storage(gpu, "plain triangles", &plain, wgpu::BufferUsages::empty()),
        })
    }

    /// The eye's view of `camera` in dispatches of as many pixels as a composite dispatch takes
    /// texels: per dispatch, the diffuse, glossy and emissive hits of `crop` kept as shading inputs,
    /// and every mirror and glass hit of the frame, in pixel order.
    pub fn run(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        camera: &Camera,
        crop: PixelRect,
    ) -> Result<(Vec<KeptPoints>, Vec<EyeHit>), GpuError> {
        let frame = camera.frame();
        let pixels = camera.width as usize * camera.height as usize;
        let chunk = GpuComposite::records_per_dispatch(gpu);
        let (nodes, triangles) = tracer.buffers();
        let mut dispatched = Vec::new();
        let mut encoders = Vec::new();
        for first in (0..pixels).step_by(chunk) {
            let count = chunk.min(pixels - first);
            let params = EyeParams {
                position: camera.position.to_array(),
                width: camera.width,
                forward: frame.forward.to_array(),
                height: camera.height,
                right: frame.right.to_array(),
                first: first as u32,
                up: frame.up.to_array(),
                count: count as u32,
                half_width: frame.half_width,
                half_height: frame.half_height,
                pad: [0; 2],
                crop: [crop.x0, crop.y0, crop.x1, crop.y1],
            };
            let size = |bytes: usize| (count * bytes) as u64;
            let inputs = output(gpu, "eye points", size(size_of::<ShadeInput>()));
            let targets = output(gpu, "eye targets", size(4));
            let others = output(gpu, "eye hits", size(size_of::<EyeHit>()));
            // Zeroed by wgpu.
            let counts = output(gpu, "eye counts", size_of::<EyeCounts>() as u64);
            let params = uniform(gpu, "eye params", bytemuck::bytes_of(&params));
            let groups = count.div_ceil(WORKGROUP_SIZE as usize) as u32;
            encoders.push(
                dispatch(
                    gpu,
                    &self.pipeline,
                    &[nodes, triangles, &params, &self.plain, &inputs, &targets, &others, &counts],
                    groups,
                )
                .finish(),
            );
            dispatched.push((inputs, targets, others, counts));
        }
        // One submission with the counts' copy: a second would wait for the first where it is made
        // (lavapipe), uncounted as a wait on the device.
        let counts = dispatched.iter().map(|(.., counts)| (counts, size_of::<EyeCounts>() as u64));
        let all_counts: Vec<EyeCounts> = read_all(gpu, encoders, counts)?;
        if let Some(c) = all_counts.iter().find(|c| c.overflow > 0) {
            return Err(GpuError::StackOverflow { ray: c.overflow as usize - 1 });
        }
        let hit_bytes = |c: &EyeCounts| u64::from(c.others) * size_of::<EyeHit>() as u64;
        let mut others: Vec<EyeHit> =
            read_all(gpu, Vec::new(), dispatched.iter().zip(&all_counts).map(|((_, _, o, _), c)| (o, hit_bytes(c))))?;
        // Appended in any order: put back in pixel order.
        others.par_sort_unstable_by_key(|h| h.pixel);
        let kept = dispatched
            .into_iter()
            .zip(&all_counts)
            .map(|((inputs, targets, ..), c)| KeptPoints { inputs, targets, count: c.kept })
            .collect();
        Ok((kept, others))
    }
}

impl EyeView for GpuBeams<'_> {
    /// On the GPU ([`GpuEye`]) where the composite will shade the frame (exact shading, the eye's
    /// level within one texture): the diffuse, glossy and emissive pixels of the region are kept
    /// there. Otherwise by the compute ray tracer, keeping none.
    fn eye_view(
        &self,
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Result<Vec<(usize, Ray, Hit)>, BackendError> {
        let pixels = camera.width as usize * camera.height as usize;
        if options.shading != Shading::Exact || !texels::fits(self.gpu, pixels) {
            return eye_by_rays(self, scene, camera);
        }
        let start = Instant::now();
        let out = checked(self.gpu, || self.eye.run(self.gpu, &self.tracer, camera, options.region()));
        self.add_times(|t| t.ray_seconds += start.elapsed().as_secs_f64());
        let (kept, others) = out?;
        *self.kept.lock().unwrap_or_else(PoisonError::into_inner) = Some(kept);
        let frame = camera.frame();
        // The tracer reports the triangle and t; the barycentric weights of the hit point follow.
        // Written in place by an indexed collect where every hit names a triangle of the scene (a
        // filtered collect gathers lists and copies them once more).
        let hit = |h: &EyeHit, tri: &Triangle| {
            let ray = camera.pixel_ray(&frame, h.pixel as usize);
            let w = tri.barycentric(ray.at(h.t)).unwrap_or_default();
            (h.pixel as usize, ray, Hit { prim: h.prim, t: h.t, u: w.y, v: w.z })
        };
        let on = |h: &EyeHit| scene.triangles.get(h.prim as usize);
        if others.par_iter().all(|h| on(h).is_some()) {
            let mut hits = Vec::with_capacity(others.len());
            others.par_iter().map(|h| hit(h, &scene.triangles[h.prim as usize])).collect_into_vec(&mut hits);
            return Ok(hits);
        }
        Ok(others.par_iter().filter_map(|h| Some(hit(h, on(h)?))).collect())
    }

    /// The kept points read back; the shader's seed of each is its pixel.
    fn take_kept_eye(&self) -> Result<Vec<TexelRadiance>, BackendError> {
        let Some(kept) = self.kept.lock().unwrap_or_else(PoisonError::into_inner).take() else {
            return Ok(Vec::new());
        };
        let sources = kept.iter().map(|k| (&k.inputs, u64::from(k.count) * size_of::<ShadeInput>() as u64));
        let inputs: Vec<ShadeInput> = checked(self.gpu, || read_all(self.gpu, Vec::new(), sources))?;
        Ok(inputs
            .par_iter()
            .map(|s| TexelRadiance {
                texel: s.seed,
                point: ShadePoint {
                    prim: s.prim,
                    p: Vec3::from_array(s.p),
                    d: Vec3::from_array(s.d),
                    seed: u64::from(s.seed),
                },
                composite: None,
            })
            .collect())
    }
}
