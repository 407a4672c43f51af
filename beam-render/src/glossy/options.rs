//! Settings of the glossy light volumes and their gather, read by both backends.

use beam_math::glossy::VolumeMethod;
use beam_scene::region::PixelRect;

/// Settings of the glossy renderer.
#[derive(Clone, Copy, Debug)]
pub struct GlossyOptions {
    /// Image width (the camera's aspect is kept from its own resolution).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// How glossy beams' Gaussian volumes are integrated.
    pub method: VolumeMethod,
    /// Gather through the cone hierarchy (`false`: every beam, as 002 does).
    pub hierarchy: bool,
    /// Second-order shadows: a scattered beam's light is checked by a shadow ray from the receiver
    /// to its source point on the scatterer (`false`: left out, as 002 does).
    pub second_order: bool,
    /// Scatterer triangles are split into `subdivide²` sub-triangles for their scattered beams (1:
    /// one beam per triangle, as 002 does).
    pub subdivide: u32,
    /// When positive, the scattered irradiance at each receiver point is read through the kernel of a
    /// photon map of that texel size (beam-cpu's `PhotonKernel`, on the CPU), for comparisons with one; 0:
    /// at the point itself.
    pub filter: f32,
    /// Only these pixels are rendered, each as in the whole frame, and the image holds just them
    /// (`None`: the whole frame; cut at the frame's edge).
    pub region: Option<PixelRect>,
}

impl GlossyOptions {
    /// Exact Gaussian volumes through the hierarchy, with second-order shadows, scatterers split
    /// 4 × 4, at `width × height`.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            method: VolumeMethod::Exact,
            hierarchy: true,
            second_order: true,
            subdivide: 4,
            filter: 0.0,
            region: None,
        }
    }

    /// The pixels rendered: [`Self::region`] within the frame, or the whole frame.
    #[must_use]
    pub fn region(&self) -> PixelRect {
        PixelRect::rendered(self.region, self.width, self.height)
    }
}
