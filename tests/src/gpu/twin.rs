//! The CPU renderer with the GPU's shading estimator: the reference GPU images are held to.

use beam_cpu::nonlinear::CpuBeams;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::nonlinear::{BeamJob, BeamRasterizer, FramePixels, KeptFrame, LevelRadiance, SMesh, TreeShading};
use beam_render::options::RenderOptions;
use beam_scene::scene;

/// The CPU renderer with the GPU's shading: [`beam_gpu::shade::twin::shade_twin`] (64 rays per
/// area light) for diffuse, glossy and emissive points, mirrors and glass by Whitted rays in waves
/// ending on it: the reference the GPU images must equal. It keeps the last radiance flow it composited (the
/// levels and the caustics).
#[derive(Default)]
pub(super) struct TwinShading(pub(super) (Vec<LevelRadiance>, Option<beam_render::irradiance_map::IrradianceMap>));

impl BeamRasterizer for TwinShading {
    fn render_beams(
        &self,
        scene: &scene::Scene,
        jobs: &[BeamJob<'_>],
    ) -> Result<Vec<beam_render::nonlinear::BeamTexture>, BackendError> {
        CpuBeams.render_beams(scene, jobs)
    }
}

impl beam_render::nonlinear::DeviceWaits for TwinShading {}
impl beam_render::nonlinear::ChildLookups for TwinShading {}

impl beam_render::nonlinear::EyeView for TwinShading {}

impl beam_render::queries::RayQueries for TwinShading {
    fn closest_hits(&self, scene: &scene::Scene, rays: &[Ray]) -> Result<Vec<Option<beam_bvh::Hit>>, BackendError> {
        CpuBeams.closest_hits(scene, rays)
    }

    fn any_hits(&self, scene: &scene::Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        CpuBeams.any_hits(scene, segments)
    }
}

impl beam_render::nonlinear::PointShading for TwinShading {
    fn shade_points(
        &mut self,
        scene: &scene::Scene,
        _options: &RenderOptions,
        caustics: Option<&beam_render::irradiance_map::IrradianceMap>,
        points: &[beam_render::nonlinear::ShadePoint],
    ) -> Result<Option<Vec<Vec3>>, BackendError> {
        use rayon::prelude::*;
        let twin = |batch: &[beam_render::nonlinear::ShadePoint]| {
            Ok(batch.par_iter().map(|s| beam_gpu::shade::twin::shade_twin(scene, caustics, 64, s)).collect())
        };
        beam_render::nonlinear::shade_by_waves(scene, &CpuBeams, &twin, points).map(Some)
    }

    fn shade_tree(
        &mut self,
        scene: &scene::Scene,
        smesh: &SMesh,
        options: &RenderOptions,
        caustics: Option<&beam_render::irradiance_map::IrradianceMap>,
        levels: &[LevelRadiance],
        _frame: KeptFrame,
    ) -> Result<TreeShading, BackendError> {
        self.0 = (levels.to_vec(), caustics.cloned());
        let shade = |points: &[beam_render::nonlinear::ShadePoint]| {
            beam_render::nonlinear::shade_points(self, &CpuBeams, scene, options, caustics, points)
        };
        let pixels = beam_render::nonlinear::composite_levels(scene, smesh, levels, shade)?;
        Ok(TreeShading::Shaded { pixels: FramePixels::Read(pixels), coarse_by_rays: Default::default() })
    }
}
