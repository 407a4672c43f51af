//! The CPU's beam renderer: texel regions by [`render_beam`], rays through the BVH, shading on the
//! host by [`shade_point`]; and a nonlinear frame rendered with it ([`render_nonlinear`]).

use crate::render::{light_seen, shade_point};
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::image::Image;
use beam_render::irradiance_map::IrradianceMap;
use beam_render::nonlinear::render_beam;
use beam_render::nonlinear::{
    BeamJob, BeamRasterizer, BeamTexture, ChildLookups, DeviceWaits, EyeView, HostShading, NonlinearError,
    NonlinearOptions, NonlinearStats, PointShading, ShadePoint, render_nonlinear_with,
};
use beam_render::options::RenderOptions;
use beam_render::queries::{BeamQueries, LightPolygon, LightQuery, LightSeen, RayQueries};
use beam_scene::scene::Scene;
use rayon::prelude::*;

/// The CPU's beam renderer: [`render_beam`] per beam, in parallel; rays through the BVH.
#[derive(Clone, Copy, Debug, Default)]
pub struct CpuBeams;

impl BeamRasterizer for CpuBeams {
    fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, BackendError> {
        Ok(jobs.par_iter().map(|j| render_beam(scene, j.beam.texel_beam(), j.size, j.exclude)).collect())
    }
}

impl RayQueries for CpuBeams {
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        Ok(rays.par_iter().map(|&ray| scene.closest_hit(ray, f32::INFINITY)).collect())
    }

    fn any_hits(&self, scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        Ok(segments.par_iter().map(|&(ray, t_max)| scene.occluded(ray, t_max)).collect())
    }
}

/// Every shadow beam traced exactly on the CPU ([`light_seen`]), in parallel; never `None`. A query
/// naming a light past `lights` is an error.
impl BeamQueries for CpuBeams {
    fn light_visibility(
        &self,
        scene: &Scene,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<Option<LightSeen>>, BackendError> {
        queries
            .par_iter()
            .map(|q| match lights.get(q.light as usize) {
                Some(light) => Ok(Some(light_seen(&scene.bvh, &scene.triangles, light, q))),
                None => Err(BackendError::new("cpu", format!("light {} of {} in a query", q.light, lights.len()))),
            })
            .collect()
    }
}

/// The CPU shades on the host ([`HostShading`]): the defaults hand the points back to it.
impl PointShading for CpuBeams {}

impl EyeView for CpuBeams {}

/// No device: all of a CPU frame is host work.
impl DeviceWaits for CpuBeams {}

/// The host looks the coarse S mesh's points up itself (the trait's default).
impl ChildLookups for CpuBeams {}

/// Every point shaded by [`shade_point`], in parallel: the host's shading of the points a GPU
/// renderer hands back.
impl HostShading for CpuBeams {
    fn shade_on_host(
        &self,
        scene: &Scene,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Vec<Vec3> {
        points.par_iter().map(|s| shade_point(scene, options, caustics, s.prim, s.p, s.d, s.seed)).collect()
    }
}

/// Render `scene` with its mirror and glass surfaces by nonlinear beams on the CPU
/// ([`render_nonlinear_with`] with [`CpuBeams`]). Fails only where the beam tree of
/// `options.bounces` levels is estimated too large to build ([`NonlinearError::BeamTree`]).
pub fn render_nonlinear(scene: &Scene, options: &NonlinearOptions) -> Result<(Image, NonlinearStats), NonlinearError> {
    render_nonlinear_with(scene, options, &mut CpuBeams, &CpuBeams)
}
