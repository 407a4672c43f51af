//! The GPU as a backend of batched visibility ([`BeamQueries`]): closest and any hits by the
//! compute ray tracer ([`RayTracer`]), exact shadow beams by [`ShadowBeams`], over one BVH upload.
//! The host-driven frames of the `ray` and `beam` methods (`beam_cpu::render::render_queries`)
//! run on it; an engine that owns its device builds it with [`Gpu::from_device`].
//!
//! [`GpuQueries::timed`] measures the device's own time in the ray and shadow-beam dispatches by
//! timestamp queries, summed across calls ([`GpuQueries::take_times`]), for benchmarks.

use crate::eye_beam::EyeBeams;
use crate::raytrace::{GpuHit, GpuRay, RayTracer, closest_of, occluded_of};
use crate::shadow_beam::{GpuLightSeen, ShadowBeams, Walk};
use crate::{Gpu, GpuError};
use beam_bvh::Hit;
use beam_bvh::gpu::GpuBvh;
use beam_math::Ray;
use beam_render::BackendError;
use beam_render::queries::{BeamQueries, LightPolygon, LightQuery, LightSeen, PixelFragments, RayQueries};
use beam_scene::scene::{Camera, Scene};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Rays and shadow beams of one scene on one device.
pub struct GpuQueries<'g> {
    gpu: &'g Gpu,
    tracer: RayTracer,
    beams: ShadowBeams,
    /// Exact primary visibility (001 §3), compiled on first use.
    eyes: std::sync::OnceLock<EyeBeams>,
    /// With [`Self::timed`]: the counters the calls add to.
    timing: Option<Timing>,
}

/// What the calls of timed queries add up ([`GpuQueries::timed`]): nanoseconds on the device by
/// timestamp queries, and the shadow beams' loop iterations.
struct Timing {
    /// Whether the device has timestamp queries.
    timestamps: bool,
    ray_nanos: AtomicU64,
    beam_nanos: AtomicU64,
    beams: AtomicU64,
    beam_iterations: AtomicU64,
}

/// The device's work in the calls of timed queries since they were made or last taken
/// ([`GpuQueries::take_times`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuTimes {
    /// Seconds on the device in the ray dispatches (closest and any hits) by timestamp queries;
    /// `None` where the device has none.
    pub ray_seconds: Option<f64>,
    /// Seconds on the device in the shadow-beam dispatches, likewise.
    pub beam_seconds: Option<f64>,
    /// Shadow beams dispatched (those that gave up past the limits included).
    pub beams: u64,
    /// Loop iterations the shadow beams ran ([`crate::shadow_beam::GpuLightSeen::work`]).
    pub beam_iterations: u64,
}

impl<'g> GpuQueries<'g> {
    /// Upload `scene`'s BVH to `gpu` and compile the ray tracer and the shadow beams.
    pub fn new(gpu: &'g Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let tracer = RayTracer::new(gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)?)?;
        let beams = ShadowBeams::sharing(gpu, &tracer)?;
        Ok(Self { gpu, tracer, beams, eyes: std::sync::OnceLock::new(), timing: None })
    }

    /// These queries with every dispatch timed on the device by timestamp queries where it has
    /// them (`PassTimer`), the times summed across calls and read by
    /// [`Self::take_times`].
    #[must_use]
    pub fn timed(mut self) -> Self {
        let timestamps = self.gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let zero = || AtomicU64::new(0);
        self.timing =
            Some(Timing { timestamps, ray_nanos: zero(), beam_nanos: zero(), beams: zero(), beam_iterations: zero() });
        self
    }

    /// What the device did in the calls since [`Self::timed`] or the last `take_times`, the
    /// counters reset to zero; `None` for queries not timed.
    pub fn take_times(&self) -> Option<GpuTimes> {
        let t = self.timing.as_ref()?;
        let seconds = |n: &AtomicU64| {
            let nanos = n.swap(0, Ordering::Relaxed);
            t.timestamps.then_some(nanos as f64 * 1e-9)
        };
        Some(GpuTimes {
            ray_seconds: seconds(&t.ray_nanos),
            beam_seconds: seconds(&t.beam_nanos),
            beams: t.beams.swap(0, Ordering::Relaxed),
            beam_iterations: t.beam_iterations.swap(0, Ordering::Relaxed),
        })
    }

    /// The hits of `rays`; timed queries add the dispatches' time on the device.
    fn trace(&self, rays: &[GpuRay]) -> Result<Vec<GpuHit>, GpuError> {
        let (hits, seconds) = self.tracer.trace_timed(self.gpu, rays, self.timing.is_some())?;
        if let Some(t) = &self.timing {
            add_seconds(&t.ray_nanos, seconds.unwrap_or(0.0));
        }
        Ok(hits)
    }

    /// These queries with shadow beams of `budget` loop iterations each (tests force the
    /// overflow path with a small one).
    #[must_use]
    pub fn with_budget(mut self, budget: u32) -> Self {
        self.beams = self.beams.with_budget(budget);
        self
    }

    /// These queries with the shadow beams walking the BVH as `walk` says.
    pub fn walking(mut self, walk: Walk) -> Result<Self, GpuError> {
        self.beams = self.beams.walking(self.gpu, walk)?;
        Ok(self)
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
        Ok(closest_of(scene, rays, self.trace(&gpu_rays)?))
    }

    fn any_hits(&self, _scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        let rays: Vec<GpuRay> = segments.par_iter().map(|(r, t_max)| GpuRay::any(r, *t_max)).collect();
        Ok(occluded_of(&self.trace(&rays)?))
    }
}

impl BeamQueries for GpuQueries<'_> {
    fn eye_fragments(
        &self,
        _scene: &Scene,
        camera: &Camera,
    ) -> Result<Option<Vec<Option<PixelFragments>>>, BackendError> {
        let eyes = match self.eyes.get() {
            Some(e) => e,
            None => {
                let made = EyeBeams::sharing(self.gpu, &self.tracer)?;
                self.eyes.get_or_init(|| made)
            }
        };
        Ok(Some(eyes.visible(self.gpu, camera)?))
    }

    fn light_visibility(
        &self,
        _scene: &Scene,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<Option<LightSeen>>, BackendError> {
        let Some(t) = &self.timing else {
            return Ok(self.beams.visibility(self.gpu, lights, queries)?);
        };
        let (answers, seconds) = self.beams.answers_timed(self.gpu, lights, queries)?;
        add_seconds(&t.beam_nanos, seconds.unwrap_or(0.0));
        t.beams.fetch_add(answers.len() as u64, Ordering::Relaxed);
        t.beam_iterations.fetch_add(answers.iter().map(|a| u64::from(a.work)).sum(), Ordering::Relaxed);
        Ok(answers.iter().map(GpuLightSeen::seen).collect())
    }
}

/// Add `seconds` to the nanoseconds of `nanos`.
fn add_seconds(nanos: &AtomicU64, seconds: f64) {
    nanos.fetch_add((seconds * 1e9).round() as u64, Ordering::Relaxed);
}
