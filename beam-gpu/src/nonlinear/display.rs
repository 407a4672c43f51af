//! A frame's pixels left on the GPU (000 §7.3 composites its frame where it is displayed): the
//! eye's level of the radiance flow as the composite wrote it, returned to the caller as the
//! frame's value ([`beam_render::nonlinear::FramePixels::Kept`], [`GpuFrame::from_device`]) where
//! the renderer is [`GpuBeams::displaying`](super::GpuBeams::displaying), or read back as the image
//! otherwise (10.5 MB a frame at 1280×1024, and host work a displayed frame does without).

use crate::{Gpu, GpuError, texels};
use beam_math::glam::Vec3;
use beam_render::nonlinear::DeviceImage;
use half::slice::{HalfBitsSliceExt, HalfFloatSliceExt};
use rayon::prelude::*;

/// The eye's radiance of a frame on the GPU: linear RGB as half floats (`Rgba16Float`, alpha
/// unused), pixel `i` (row-major) at texel `(i mod w, i / w)` of a texture `w` texels wide. One
/// frame's; whoever holds it owns the texture.
pub struct GpuFrame {
    pub(super) texture: wgpu::Texture,
    /// Pixels of the frame.
    pub(super) len: usize,
}

impl GpuFrame {
    /// The texture. For a frame of a [`GpuBeams::displaying`](super::GpuBeams::displaying) renderer it is the image's own
    /// width × height (pixel `(x, y)` at texel `(x, y)`), to sample or copy to a surface; its
    /// usages are `TEXTURE_BINDING | STORAGE_BINDING | COPY_SRC`.
    #[must_use]
    pub fn texture(&self) -> &wgpu::Texture {
        &self.texture
    }

    /// The pixels read back and widened to `f32` (row-major): 8 bytes a pixel read back, converted
    /// eight pixels an item (F16C where the CPU has it) straight from where they are mapped.
    pub fn read_back(&self, gpu: &Gpu) -> Result<Vec<Vec3>, GpuError> {
        texels::read_back_with(gpu, &self.texture, |halves: &[[u16; 4]]| {
            let halves = &halves[..self.len.min(halves.len())];
            // Rayon's indexed collect writes each item in place, so no pass zeroes the image
            // first (16 MB of page faults on one thread).
            let eights: Vec<[Vec3; 8]> = halves
                .par_chunks(8)
                .map(|h| {
                    let mut rgba = [0.0f32; 32];
                    let bits: &[u16] = bytemuck::cast_slice(h);
                    bits.reinterpret_cast::<half::f16>().convert_to_f32_slice(&mut rgba[..bits.len()]);
                    std::array::from_fn(|k| Vec3::new(rgba[4 * k], rgba[4 * k + 1], rgba[4 * k + 2]))
                })
                .collect();
            let mut pixels: Vec<Vec3> = bytemuck::allocation::cast_vec(eights);
            pixels.truncate(halves.len());
            pixels
        })
    }
}

impl GpuFrame {
    /// The frame a [`GpuBeams::displaying`](super::GpuBeams::displaying) renderer left on the GPU,
    /// as `beam_cpu`'s `render_nonlinear_frame` hands it over ([`DeviceImage`]); the image back
    /// where it is another backend's.
    pub fn from_device(image: DeviceImage) -> Result<Self, DeviceImage> {
        image.downcast()
    }
}
