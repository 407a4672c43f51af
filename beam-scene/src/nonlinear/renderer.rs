//! The narrow interface of a nonlinear backend: render a level's beams into texels, find the
//! nearest hits of rays, and, where it can, shade points and run the radiance flow itself.

use super::radiance::LevelRadiance;
use super::smesh::SMesh;
use super::texture::{BeamJob, BeamTexture, ShadePoint};
use crate::irradiance_map::IrradianceMap;
use crate::options::RenderOptions;
use crate::scene::Scene;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;

/// Renders batches of beams into their texel regions (beam-cpu's `CpuBeams`: each beam in
/// parallel; beam-gpu's `GpuBeams`: per-level atlases, 000 §3) and traces rays. Shading is optional:
/// where a backend returns `Ok(None)` the caller shades on the CPU.
pub trait BeamRenderer: Sync {
    /// The textures of `jobs`, in order: nearest hits only (000 Alg. 1).
    fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, String>;

    /// The nearest hit of every ray (the eye's view; the reference's Whitted rays), with its
    /// barycentric coordinates.
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, String>;

    /// The radiance of every point as beam-cpu's `shade_point` computes it, or `Ok(None)` when this
    /// backend does not shade with `options` (the default: the caller shades them on the CPU).
    fn shade_points(
        &self,
        scene: &Scene,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Result<Option<Vec<Vec3>>, String> {
        let _ = (scene, options, caustics, points);
        Ok(None)
    }

    /// The radiance flow of a built tree (`levels[0]` the eye's view): the eye's pixels, or
    /// `Ok(None)` when this backend does not run it (the default: beam-cpu's `composite_levels`).
    fn shade_tree(
        &self,
        scene: &Scene,
        smesh: &SMesh,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        levels: &[LevelRadiance],
    ) -> Result<Option<Vec<Vec3>>, String> {
        let _ = (scene, smesh, options, caustics, levels);
        Ok(None)
    }
}
