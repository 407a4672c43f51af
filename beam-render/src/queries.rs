//! Ray queries, under one vocabulary for every renderer and backend: a callback for one ray
//! ([`AnyHit`], [`ClosestHit`]) or a backend's batch of them ([`RayQueries`]), and exact shadow beams
//! in batches ([`BeamQueries`]).

use crate::error::BackendError;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::{Vec2, Vec3};
use beam_scene::scene::{Camera, Scene};

/// Whether `ray` meets a triangle at a parameter below `t_max` (a shadow ray or segment).
pub type AnyHit<'a> = dyn Fn(Ray, f32) -> bool + Sync + 'a;

/// The nearest triangle `ray` meets and the ray parameter there.
pub type ClosestHit<'a> = dyn Fn(Ray) -> Option<(u32, f32)> + Sync + 'a;

/// Ray queries against a scene, in batches (beam-cpu: its BVH; beam-gpu: the compute ray tracer).
/// A backend that can fail (a GPU's device) says why in a [`BackendError`].
pub trait RayQueries: Sync {
    /// The nearest hit of every ray, with the barycentric weights of the hit point (the eye's view;
    /// the Whitted rays past the beam tree).
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError>;

    /// Whether each segment `(ray, t_max)` meets a triangle before `t_max` (shadow rays).
    fn any_hits(&self, scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError>;
}

/// Most corners of a [`LightPolygon`].
pub const MAX_LIGHT_CORNERS: usize = 8;

/// A convex emitting polygon as a shadow beam sees it: its corners (either winding) and the unit
/// normal of the side it lights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPolygon {
    /// Corners; the first `count` are used.
    pub corners: [Vec3; MAX_LIGHT_CORNERS],
    /// Number of corners, 3 to [`MAX_LIGHT_CORNERS`].
    pub count: u32,
    /// Unit normal of the lit side.
    pub normal: Vec3,
}

impl LightPolygon {
    /// The polygon `corners` (3 to [`MAX_LIGHT_CORNERS`] of them) lighting the side of `normal`;
    /// `None` for another number of corners.
    #[must_use]
    pub fn new(corners: &[Vec3], normal: Vec3) -> Option<Self> {
        if !(3..=MAX_LIGHT_CORNERS).contains(&corners.len()) {
            return None;
        }
        let mut c = [Vec3::ZERO; MAX_LIGHT_CORNERS];
        c[..corners.len()].copy_from_slice(corners);
        Some(Self { corners: c, count: corners.len() as u32, normal })
    }

    /// The corners in use.
    #[must_use]
    pub fn corners(&self) -> &[Vec3] {
        &self.corners[..self.count as usize]
    }
}

/// A shadow-beam query: how much of light `light` (an index into the lights of the batch) point
/// `p` with unit normal `n` sees (001 §5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightQuery {
    /// The shade point (already offset off its surface).
    pub p: Vec3,
    /// Its unit normal.
    pub n: Vec3,
    /// Index of the light in the batch's list.
    pub light: u32,
    /// Clip the light to the half-space above `p`'s tangent plane before the beam is built
    /// (exact shading, 001 eq. 1); without it the whole light is the beam (`Shading::Fraction`).
    pub clip_above: bool,
}

/// What a shadow beam found: the exact irradiance per unit radiance of the visible part of the
/// light (Lambert's formula over the unoccluded pieces, 001 eq. 1 with a Lambertian BRDF) and the
/// visible fraction of the beam's cross-section (001 eq. 2's visibility).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LightSeen {
    /// Irradiance per unit radiance of the unoccluded pieces.
    pub irradiance: f32,
    /// Unoccluded share of the beam's cross-section, in `[0, 1]`.
    pub fraction: f32,
}

/// A triangle seen through a pixel by exact primary visibility (001 §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelFragment {
    /// Input index of the triangle.
    pub prim: u32,
    /// Share of the pixel's square it covers (its box-filter weight).
    pub coverage: f32,
    /// Centroid of its visible part in continuous pixel coordinates (origin at the image's
    /// top-left corner, y down): the camera's ray through it is the fragment's centroid ray.
    pub centroid: Vec2,
}

/// What a pixel sees: its triangles and the background, whose coverages sum to one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PixelFragments {
    /// The triangles seen, each once.
    pub fragments: Vec<PixelFragment>,
    /// Share of the pixel that sees no triangle.
    pub background: f32,
    /// Centroid of that share in continuous pixel coordinates (the pixel's centre when none).
    pub background_centroid: Vec2,
}

/// Exact shadow beams in batches (beam-cpu: its beam tracer; beam-gpu: the compute shadow beams).
pub trait BeamQueries: RayQueries {
    /// Exact primary visibility of every pixel of `camera` (row-major; eye beams, 001 §3):
    /// `Ok(None)` from a backend without eye beams; a pixel `None` where the backend stopped short
    /// (the caller computes it).
    fn eye_fragments(
        &self,
        scene: &Scene,
        camera: &Camera,
    ) -> Result<Option<Vec<Option<PixelFragments>>>, BackendError> {
        let _ = (scene, camera);
        Ok(None)
    }

    /// The answer to each query: `None` where the backend could not finish a beam within its limits
    /// (pieces or work past a fixed capacity); the caller then traces that beam on its own path,
    /// so that nothing is dropped.
    fn light_visibility(
        &self,
        scene: &Scene,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<Option<LightSeen>>, BackendError>;
}
