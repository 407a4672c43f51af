//! A frame's pixels left on the GPU (000 §7.3 composites its frame where it is displayed): the
//! eye's level of the radiance flow as the composite wrote it, handed to the caller by
//! [`GpuBeams::take_frame`] where the renderer is [`GpuBeams::displaying`], or read back as the
//! image otherwise (10.5 MB a frame at 1280×1024, and host work a displayed frame does without).

use super::atlas::GpuBeams;
use crate::{Gpu, GpuError, texels};
use beam_math::glam::Vec3;
use half::slice::{HalfBitsSliceExt, HalfFloatSliceExt};
use rayon::prelude::*;
use std::sync::PoisonError;

/// The eye's radiance of a frame on the GPU: linear RGB as half floats (`Rgba16Float`, alpha
/// unused), pixel `i` (row-major) at texel `(i mod w, i / w)` of a texture `w` texels wide.
pub struct GpuFrame {
    pub(super) texture: wgpu::Texture,
    /// Pixels of the frame.
    pub(super) len: usize,
}

impl GpuFrame {
    /// The texture. For a frame of a [`GpuBeams::displaying`] renderer it is the image's own
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

impl GpuBeams<'_> {
    /// This renderer, leaving each frame's pixels on the GPU for display rather than reading them
    /// back: where the GPU composites the frame (exact shading, each level within one texture of
    /// the device), `beam_cpu`'s `render_nonlinear_frame` returns no image and
    /// [`take_frame`](Self::take_frame) hands over the frame, in a texture of the whole image's
    /// size (pixels outside a `region` black); elsewhere the image comes back as before.
    #[must_use]
    pub fn displaying(mut self) -> Self {
        self.display = true;
        self
    }

    /// The last frame this renderer kept for display (see [`displaying`](Self::displaying)), once.
    pub fn take_frame(&self) -> Option<GpuFrame> {
        self.frame.lock().unwrap_or_else(PoisonError::into_inner).take()
    }
}
