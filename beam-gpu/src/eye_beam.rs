//! Exact primary visibility on the GPU (`shaders/eye_beam.wgsl`, entry point `eye_fragments`): per
//! pixel, the eye beam through the pixel's square traverses beam-bvh's GPU layout front to back and
//! is split exactly into pieces, each owned by the nearest triangle seen through it (001 §3: splits
//! at triangle edges with the quad rules of 001 §3.2, `shaders/lib/quad.wgsl`; where two triangles
//! overlap, along the straight line where their depths are equal, since `1/s` is affine over the
//! image plane). Each pixel reports its [`PixelFragments`]: every triangle it sees with the share
//! of the pixel it covers (exact box-filtered coverage) and the centroid of its pieces, and the
//! share that sees the background. CPU twin: `beam_cpu::render::visible_surface` over the pixel's
//! square.
//!
//! A pixel holds at most [`MAX_EYE_PIECES`] pieces and [`MAX_FRAGMENTS`] triangles, and runs at
//! most its budget of loop iterations ([`EyeBeams::budget`]); past any of these (or where
//! llvmpipe's loop cap cut its loops short) it answers `None`, never a wrong value.

use crate::buffers::{buffer_entry, checked, encode_pass, max_binding, output, read_back, uniform};
use crate::bvh_pass::BvhPass;
use crate::interface::{EYE_DONE, MISS};
use crate::raytrace::RayTracer;
use crate::{Gpu, GpuError};
use beam_bvh::gpu::GpuBvh;
use beam_math::glam::Vec2;
use beam_math::polybeam::BeamFrame;
use beam_render::queries::{PixelFragment, PixelFragments};
use beam_scene::scene::Camera;
use bytemuck::{Pod, Zeroable};

pub use crate::bvh_pass::{HARDWARE_BUDGET, SOFTWARE_BUDGET};
pub use crate::interface::{MAX_EYE_PIECES, MAX_FRAGMENTS};

/// The parameters of one dispatch: the camera's image plane as a beam frame and the pixels.
///
/// WGSL twin: `EyeBeamParams` in `shaders/eye_beam.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct EyeBeamParams {
    /// The eye.
    pub apex: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// The ray from the eye to the image's top-left corner on the image plane (relative to the eye,
    /// so that a far eye's coordinates cost no precision).
    pub corner_ray: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Unit axis of the image plane to the right.
    pub u: [f32; 3],
    /// First pixel (row-major) of the dispatch.
    pub first: u32,
    /// Unit axis of the image plane down the image.
    pub v: [f32; 3],
    /// Pixels of the dispatch.
    pub count: u32,
    /// Unit normal of the image plane, away from the eye.
    pub normal: [f32; 3],
    /// Loop iterations a pixel may run.
    pub budget: u32,
    /// A pixel's width and height on the image plane.
    pub pixel: [f32; 2],
    /// Distance from the eye to the image plane.
    pub plane_distance: f32,
    /// Padding.
    pub pad: u32,
}

/// A triangle seen in a pixel, as the shader writes it.
///
/// WGSL twin: `EyeFragment` in `shaders/eye_beam.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuFragment {
    /// Input index of the triangle.
    pub prim: u32,
    /// Share of the pixel it covers.
    pub coverage: f32,
    /// Centroid of its pieces in pixel-local coordinates (`[0, 1]²`, y down).
    pub centroid: [f32; 2],
}

/// A pixel's answer as the shader writes it.
///
/// WGSL twin: `EyePixel` in `shaders/eye_beam.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuPixel {
    /// [`EYE_DONE`], or why the pixel stopped short ([`crate::interface::EYE_PIECES`],
    /// [`crate::interface::EYE_BUDGET`], [`crate::interface::EYE_CUT`],
    /// [`crate::interface::EYE_FRAGMENTS`]).
    pub status: u32,
    /// Fragments used.
    pub count: u32,
    /// Loop iterations the pixel ran.
    pub work: u32,
    /// Share of the pixel that sees the background.
    pub background: f32,
    /// Centroid of that share, pixel-local.
    pub background_centroid: [f32; 2],
    /// Padding.
    pub pad: [u32; 2],
    /// The triangles seen.
    pub fragments: [GpuFragment; MAX_FRAGMENTS as usize],
}

const _: () = assert!(
    size_of::<EyeBeamParams>() == 96
        && size_of::<GpuFragment>() == 16
        && size_of::<GpuPixel>() == 32 + 16 * MAX_FRAGMENTS as usize
);

impl GpuPixel {
    /// The answer for pixel `(x, y)`, `None` for a pixel that stopped short.
    #[must_use]
    pub fn fragments(&self, x: u32, y: u32) -> Option<PixelFragments> {
        if self.status != EYE_DONE {
            return None;
        }
        let at = Vec2::new(x as f32, y as f32);
        let fragments = self.fragments[..(self.count as usize).min(self.fragments.len())]
            .iter()
            .filter(|f| f.prim != MISS)
            .map(|f| PixelFragment { prim: f.prim, coverage: f.coverage, centroid: at + Vec2::from(f.centroid) })
            .collect();
        Some(PixelFragments {
            fragments,
            background: self.background,
            background_centroid: at + Vec2::from(self.background_centroid),
        })
    }
}

/// Pixels per dispatch (a workgroup count under 65,535).
const CHUNK: usize = 1 << 18;

/// The compiled pipeline, over a BVH already on the device.
pub struct EyeBeams {
    pass: BvhPass,
}

impl EyeBeams {
    const ENTRY: (&str, &str) = ("eye_beam", "eye_fragments");

    /// Compile `eye_beam.wgsl` and upload `bvh` (each of its buffers within one storage binding,
    /// [`GpuError::SceneTooLarge`]).
    pub fn new(gpu: &Gpu, bvh: &GpuBvh) -> Result<Self, GpuError> {
        Ok(Self { pass: BvhPass::new(gpu, Self::ENTRY, bvh)? })
    }

    /// Compile `eye_beam.wgsl` over the BVH `tracer` uploaded (its buffers shared).
    pub fn sharing(gpu: &Gpu, tracer: &RayTracer) -> Result<Self, GpuError> {
        Ok(Self { pass: BvhPass::sharing(gpu, Self::ENTRY, tracer)? })
    }

    /// These beams with a budget of `budget` loop iterations a pixel (tests force the overflow path).
    #[must_use]
    pub fn with_budget(mut self, budget: u32) -> Self {
        self.pass.budget = budget;
        self
    }

    /// Loop iterations a pixel may run before it answers `None`.
    #[must_use]
    pub fn budget(&self) -> u32 {
        self.pass.budget
    }

    /// What each pixel of `camera` (row-major, `width × height`) sees, `None` for a pixel that
    /// stopped short. A camera without a view ([`Camera::check_view`]) sees nothing: no pixels.
    pub fn visible(&self, gpu: &Gpu, camera: &Camera) -> Result<Vec<Option<PixelFragments>>, GpuError> {
        let w = camera.width.max(1);
        let pixels = self.pixels(gpu, camera)?;
        Ok(pixels.iter().zip(0u32..).map(|(p, i)| p.fragments(i % w, i / w)).collect())
    }

    /// The shader's answers as they are (with their status and work), row-major.
    pub fn pixels(&self, gpu: &Gpu, camera: &Camera) -> Result<Vec<GpuPixel>, GpuError> {
        let Some(base) = image_params(camera, self.pass.budget) else { return Ok(Vec::new()) };
        let total = camera.width as usize * camera.height as usize;
        let chunk = CHUNK.min((max_binding(gpu) / size_of::<GpuPixel>() as u64) as usize).max(1);
        checked(gpu, || {
            let mut out = Vec::with_capacity(total);
            for first in (0..total).step_by(chunk) {
                let count = chunk.min(total - first);
                let params = EyeBeamParams { first: first as u32, count: count as u32, ..base };
                let params = uniform(gpu, "eye beam params", bytemuck::bytes_of(&params));
                let size = (count * size_of::<GpuPixel>()) as u64;
                let seen = output(gpu, "eye pixels", size);
                let [nodes, triangles] = self.pass.bvh_entries();
                let entries = [nodes, triangles, buffer_entry(2, &params), buffer_entry(3, &seen)];
                let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
                encode_pass(gpu, &mut encoder, &self.pass.pipeline, count as u32, &entries);
                out.extend(read_back::<GpuPixel>(gpu, encoder, &seen, size)?);
            }
            Ok(out)
        })
    }
}

/// The image plane of `camera` as the shader takes it: beam-cpu's image frame (the plane at
/// distance 1 along the view, `u` right, `v` down the image), `None` without a view.
fn image_params(camera: &Camera, budget: u32) -> Option<EyeBeamParams> {
    camera.check_view().ok()?;
    let f = camera.frame();
    let frame = BeamFrame::new(camera.position, camera.position + f.forward, f.forward, f.right)?;
    // Beam-cpu's frame: the image plane through its (rounded) origin; the corner ray in f64, so that
    // it keeps the pixels' places to a small share of a pixel however far the eye is from the origin.
    let (u, v) = (frame.u.as_dvec3(), frame.v.as_dvec3());
    let corner =
        (frame.origin.as_dvec3() - frame.apex.as_dvec3()) - f64::from(f.half_width) * u - f64::from(f.half_height) * v;
    let pixel = Vec2::new(2.0 * f.half_width / camera.width as f32, 2.0 * f.half_height / camera.height as f32);
    Some(EyeBeamParams {
        apex: frame.apex.to_array(),
        width: camera.width,
        corner_ray: corner.as_vec3().to_array(),
        height: camera.height,
        u: frame.u.to_array(),
        first: 0,
        v: frame.v.to_array(),
        count: 0,
        normal: frame.normal.to_array(),
        budget,
        pixel: pixel.to_array(),
        plane_distance: frame.distance,
        pad: 0,
    })
}
