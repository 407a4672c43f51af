//! Render settings: how area lights' visibility and shading are computed, at what size, with what
//! samples. Both backends read them.

use beam_scene::region::PixelRect;

/// How the visibility of area lights is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Exact: a shadow beam per shade point, split at triangle edges (001 §5). Noise-free.
    Beam,
    /// `spp` stratified shadow rays per shade point and light (the reference).
    Ray,
}

/// How visibility turns into irradiance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// 001 eq. 2: a point source at the light's centre times the visible fraction.
    Fraction,
    /// 001 eq. 1 for Lambertian surfaces: Lambert's formula over the visible polygons (beam), or
    /// the Monte-Carlo estimate of the same integral with the same samples (ray).
    Exact,
}

/// Render settings.
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Visibility method.
    pub method: Method,
    /// Shading of area lights.
    pub shading: Shading,
    /// Shadow rays per shade point and area light ([`Method::Ray`]).
    pub spp: u32,
    /// Primary rays per pixel, stratified and jittered, averaged (a box filter), when primary
    /// visibility is ray traced.
    pub primary_spp: u32,
    /// With [`Method::Beam`]: primary visibility by eye beams with exact box-filtered coverage
    /// (`true`; fast on small scenes, but tiles that see background or much hidden geometry traverse
    /// far and fragment: minutes on the 277k-triangle conference room), or by primary rays like
    /// [`Method::Ray`] (`false`, as 001 §5.1 times soft shadows).
    pub primary_beams: bool,
    /// Image width (the camera's aspect is kept from the camera's own resolution).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Seed of the shadow-ray samples.
    pub seed: u64,
    /// Only these pixels of the `width × height` frame are rendered, each to the value it has in
    /// the whole frame's render, and the image returned holds just them (a render farm's tile);
    /// `None`: the whole frame. A rectangle reaching past the frame is cut at its edge.
    pub region: Option<PixelRect>,
    /// With [`Method::Beam`]: how a shadow beam takes its occluders. The choices give the same
    /// image.
    pub occluders: Occluders,
    /// With [`Method::Beam`]: every shadow beam is traced to the end (`true`). By default
    /// (`false`) a beam whose work passes `spp` shadow rays' worth leaves the part of the light it
    /// has not resolved to `spp` rays (the ratio estimator: exact where they all agree), so that a
    /// render never costs much more than the ray method's; the stats give the share of exact pixels
    /// and the largest error bound.
    pub exact: bool,
}

/// How shadow beams take their occluders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Occluders {
    /// Each cluster of shade points picks whichever of the two below did less work on its first
    /// beam that its candidates split enough for the edges to be worth building.
    #[default]
    Auto,
    /// One at a time: each splits the beam's remaining pieces (001 §3.2).
    Split,
    /// By their edges: the winding number of the projected silhouette, boundary and cut edges,
    /// integrated exactly over the light (the cost follows the edges that do not cancel).
    Edges,
}

impl RenderOptions {
    /// Exact shading by shadow beams (001 eq. 1) traced to the end at `width × height`, one primary
    /// ray per pixel centre: the shading the nonlinear renderer and its references share.
    #[must_use]
    pub fn exact(width: u32, height: u32) -> Self {
        Self {
            method: Method::Beam,
            shading: Shading::Exact,
            spp: 1,
            primary_spp: 1,
            primary_beams: false,
            width,
            height,
            seed: 1,
            region: None,
            occluders: Occluders::Auto,
            exact: true,
        }
    }

    /// The pixels rendered: [`Self::region`] within the frame, or the whole frame.
    #[must_use]
    pub fn region(&self) -> PixelRect {
        PixelRect::rendered(self.region, self.width, self.height)
    }
}
