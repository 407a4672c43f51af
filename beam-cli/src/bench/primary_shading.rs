//! What every tracer of `beam bench primary` shares, on the CPU and the GPU alike: the flat shading
//! under comparison (the sample positions of each pixel are `beam_cpu::render::pixel_samples`).

use beam_math::glam::Vec3;
use beam_scene::scene::Scene;

/// A fixed colour of triangle `prim`, each channel in `[0.15, 1]` (a hash of the index).
#[must_use]
pub(super) fn albedo(prim: u32) -> Vec3 {
    let h = (u64::from(prim) + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let h = (h ^ (h >> 29)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let c = |s: u32| 0.15 + 0.85 * ((h >> s) & 0xFF) as f32 / 255.0;
    Vec3::new(c(8), c(24), c(40))
}

/// The flat shading under comparison: triangle `prim`'s colour times `|cos|` of the angle between
/// its normal and the unit view direction `d`.
pub(super) fn flat(scene: &Scene) -> impl Fn(u32, Vec3, Vec3) -> Vec3 + Sync + '_ {
    move |prim, _, d| albedo(prim) * scene.normal(prim).dot(d).abs()
}
