//! The GPU as a backend of batched visibility ([`BeamQueries`]): closest and any hits by the
//! compute ray tracer ([`RayTracer`]), exact shadow beams by [`ShadowBeams`], over one BVH upload.
//! The host-driven frames of the `ray` and `beam` methods (`beam_cpu::render::render_queries`)
//! run on it; an engine that owns its device builds it with [`Gpu::from_device`].

use crate::raytrace::{GpuRay, RayTracer, closest_of, occluded_of};
use crate::shadow_beam::ShadowBeams;
use crate::{Gpu, GpuError};
use beam_bvh::Hit;
use beam_bvh::gpu::GpuBvh;
use beam_math::Ray;
use beam_scene::BackendError;
use beam_scene::queries::{BeamQueries, LightPolygon, LightQuery, LightSeen, RayQueries};
use beam_scene::scene::Scene;
use rayon::prelude::*;

/// Rays and shadow beams of one scene on one device.
pub struct GpuQueries<'g> {
    gpu: &'g Gpu,
    tracer: RayTracer,
    beams: ShadowBeams,
}

impl<'g> GpuQueries<'g> {
    /// Upload `scene`'s BVH to `gpu` and compile the ray tracer and the shadow beams.
    pub fn new(gpu: &'g Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let tracer = RayTracer::new(gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)?)?;
        let beams = ShadowBeams::sharing(gpu, &tracer)?;
        Ok(Self { gpu, tracer, beams })
    }

    /// These queries with shadow beams of `budget` loop iterations each (tests force the
    /// overflow path with a small one).
    #[must_use]
    pub fn with_budget(mut self, budget: u32) -> Self {
        self.beams = self.beams.with_budget(budget);
        self
    }

    /// The device.
    #[must_use]
    pub fn gpu(&self) -> &Gpu {
        self.gpu
    }
}

impl RayQueries for GpuQueries<'_> {
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        let gpu_rays: Vec<GpuRay> = rays.par_iter().map(GpuRay::closest).collect();
        Ok(closest_of(scene, rays, self.tracer.trace(self.gpu, &gpu_rays)?))
    }

    fn any_hits(&self, _scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        let rays: Vec<GpuRay> = segments.par_iter().map(|(r, t_max)| GpuRay::any(r, *t_max)).collect();
        Ok(occluded_of(&self.tracer.trace(self.gpu, &rays)?))
    }
}

impl BeamQueries for GpuQueries<'_> {
    fn light_visibility(
        &self,
        _scene: &Scene,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<Option<LightSeen>>, BackendError> {
        Ok(self.beams.visibility(self.gpu, lights, queries)?)
    }
}
