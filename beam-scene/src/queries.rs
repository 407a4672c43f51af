//! Ray queries, under one vocabulary for every renderer and backend: a callback for one ray
//! ([`AnyHit`], [`ClosestHit`]) or a backend's batch of them ([`RayQueries`]).

use crate::error::BackendError;
use crate::scene::Scene;
use beam_bvh::Hit;
use beam_math::Ray;

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
