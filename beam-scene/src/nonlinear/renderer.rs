//! The narrow interfaces a nonlinear backend implements, each named for what it does: ray queries
//! (nearest hits with barycentric weights, any hits), a beam rasterizer (beams and scene triangles
//! to texels, 000 Alg. 1) and point shading (hit to radiance, where the backend can). A renderer
//! is their composition ([`BeamRenderer`]): beam-cpu's `CpuBeams` and beam-gpu's `GpuBeams` are two.
//! A backend that can fail returns a [`BackendError`] (the CPU's never fails); its message is the
//! backend's own.

use super::radiance::LevelRadiance;
use super::smesh::SMesh;
use super::texture::{BeamJob, BeamTexture, ShadePoint};
use crate::error::BackendError;
use crate::irradiance_map::IrradianceMap;
use crate::options::RenderOptions;
use crate::queries::RayQueries;
use crate::scene::Scene;
use beam_math::glam::Vec3;

/// Renders a tree level's beams into their texel regions: the nearest scene hit of every texel's
/// ray (000 Alg. 1; beam-cpu: each beam in parallel; beam-gpu: per-level atlases, 000 §3).
pub trait BeamRasterizer: Sync {
    /// The textures of `jobs`, in order.
    fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, BackendError>;
}

/// Shades points where a backend can; `Ok(None)` hands the work back to the caller, which shades on
/// the CPU (both methods' default).
pub trait PointShading: Sync {
    /// The radiance of every point as beam-cpu's `shade_point` computes it, or `Ok(None)` when this
    /// backend does not shade with `options`.
    fn shade_points(
        &self,
        scene: &Scene,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Result<Option<Vec<Vec3>>, BackendError> {
        let _ = (scene, options, caustics, points);
        Ok(None)
    }

    /// The radiance flow of a built tree (`levels[0]` the eye's view): the eye's pixels, or
    /// `Ok(None)` when this backend does not run it (beam-cpu's `composite_levels` then does).
    fn shade_tree(
        &self,
        scene: &Scene,
        smesh: &SMesh,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        levels: &[LevelRadiance],
    ) -> Result<Option<Vec<Vec3>>, BackendError> {
        let _ = (scene, smesh, options, caustics, levels);
        Ok(None)
    }
}

/// How long a backend has blocked on a device, so that a frame's host work (000 Table 2's CPU
/// share) is its wall time less these waits. A backend on the CPU has none (the default).
pub trait DeviceWaits: Sync {
    /// Seconds spent blocked on the device so far.
    fn waited_seconds(&self) -> f64 {
        0.0
    }
}

/// What the nonlinear renderer needs of a backend: ray queries, a beam rasterizer, (optional)
/// point shading and its device waits. Implemented for every type that has the four.
pub trait BeamRenderer: RayQueries + BeamRasterizer + PointShading + DeviceWaits {}

impl<T: RayQueries + BeamRasterizer + PointShading + DeviceWaits> BeamRenderer for T {}
