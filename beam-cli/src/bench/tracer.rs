//! What every benchmarked ray tracer answers: ours and the peers alike.

use beam_math::Ray;

/// A ray tracer under test: ours or a peer, over the same triangles.
pub(super) trait Tracer: Sync {
    /// Display name.
    fn name(&self) -> String;
    /// Build time in milliseconds.
    fn build_ms(&self) -> f64;
    /// Distance to the closest hit.
    fn closest(&self, ray: &Ray) -> Option<f32>;
    /// True when something lies on the ray before `t_max`.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool;
}
