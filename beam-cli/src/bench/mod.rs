//! `beam bench`: benchmarks that print ratios against peers measured in the same run.

pub mod bvh;
pub mod glossy;
pub mod gpu;
pub mod nonlinear;
#[cfg(feature = "peers")]
mod peers;
pub mod primary;
pub mod primary_sweep;
pub mod softshadow;

use beam_math::Ray;

/// A ray tracer under test: ours or a peer, over the same triangles.
pub trait Tracer: Sync {
    /// Display name.
    fn name(&self) -> String;
    /// Build time in milliseconds.
    fn build_ms(&self) -> f64;
    /// Distance to the closest hit.
    fn closest(&self, ray: &Ray) -> Option<f32>;
    /// True when something lies on the ray before `t_max`.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool;
}

/// The peers available in this build (none without the `peers` feature).
pub fn peers(triangles: &[beam_math::Triangle]) -> Result<Vec<Box<dyn Tracer>>, String> {
    #[cfg(feature = "peers")]
    return peers::all(triangles);
    #[cfg(not(feature = "peers"))]
    {
        let _ = triangles;
        Ok(Vec::new())
    }
}
