//! The sky: a constant environment shaded by beams as the six faces of a cube about the scene
//! (each face's share of the samples, and its exact shading), or sampled as the ray method samples
//! it, by cosine-weighted rays (a map; a constant sky with rays, or behind cut-outs).

use super::context::{Context, Thread};
use super::light_samples::{cosine_direction, light_sample, tangents};
use crate::render::lambert::polygon_irradiance;
use beam_math::glam::Vec3;
use beam_render::options::Shading;
use rand_pcg::Pcg32;

impl Context<'_> {
    /// The shadow rays that sample area light `index` at `p` (normal `n`): `--spp` for the
    /// scene's lights; for a face of a constant environment ([`Environment::lights`]), its share of
    /// them, the face's part of the sky's unoccluded irradiance `πL` (at least one), so that the
    /// sky as a whole costs a point about `--spp` rays, like one light, and not six times that.
    pub(super) fn samples(&self, p: Vec3, n: Vec3, index: usize) -> u32 {
        let spp = self.options.spp.max(1);
        if index < self.scene.lights.len() {
            return spp;
        }
        let share = polygon_irradiance(p, n, self.emitters[index].polygon()) / std::f32::consts::PI;
        ((spp as f32 * share).ceil() as u32).clamp(1, spp)
    }

    /// How area light `index` is shaded: by `--shading` for the scene's lights; exactly (001 eq. 1)
    /// for a constant environment's faces, which eq. 2's point source at a face's centre would
    /// misrepresent (they surround the scene), so that the sky gives `πL` under either setting.
    pub(super) fn shading(&self, index: usize) -> Shading {
        if index < self.scene.lights.len() { self.options.shading } else { Shading::Exact }
    }

    /// Irradiance at `p` (normal `n`) from the scene's environment, sampled: `--spp`
    /// cosine-weighted directions over the hemisphere about `n` (stratified as the lights' samples
    /// are, [`light_sample`]), each traced as a shadow ray to infinity; those that leave the scene
    /// bring the environment's radiance from their direction, and the estimate is `π/N Σ L(ωᵢ)` (the
    /// cosine and the density `cos θ / π` cancel): exact for a constant sky wherever it is wholly
    /// open. For a map with either method (a map is not constant over any polygon a beam could
    /// integrate exactly), and for a constant sky with rays (fewer rays, and less noise, than
    /// sampling its six faces as lights). Counted as environment rays, and its bound `π·max L`
    /// (the estimate and the exact value both lie in `[0, π·max L]`) added to the point's error
    /// bound.
    pub(super) fn environment_irradiance(&self, p: Vec3, n: Vec3, rng: &mut Pcg32, t: &mut Thread) -> Vec3 {
        let environment = &self.scene.environment;
        let spp = self.options.spp.max(1);
        let (u, v) = tangents(n);
        let mut sum = Vec3::ZERO;
        let mut last = None;
        for i in 0..spp {
            let w = cosine_direction((u, v, n), light_sample(i, spp, rng));
            if t.surface.is_some_and(|s| s.dot(w) <= 0.0) {
                // Below the surface itself (under a normal texture's bent normal): hidden.
                continue;
            }
            t.c.environment_rays += 1;
            if !self.occluded((p, w), f32::INFINITY, &mut last) {
                sum += environment.radiance(w);
            }
        }
        t.c.pending_bound += std::f32::consts::PI * environment.max_radiance();
        std::f32::consts::PI * sum / spp as f32
    }

    /// Whether a constant sky, shaded by beams as the six faces of a cube ([`Context::lights`]),
    /// is sampled at `p` (normal `n`) by the ray method's cosine-weighted rays instead: where a
    /// cut-out may hide one of the faces that light the point, those rays (which see through it)
    /// are less noisy than sampling the faces one by one.
    pub(super) fn sky_behind_cut_outs(&self, p: Vec3, n: Vec3, t: &mut Thread) -> bool {
        self.cut_outs.is_some()
            && (self.scene.lights.len()..self.lights.len()).any(|i| {
                let e = &self.emitters[i];
                e.may_light(p, n, true) && self.cut_outs_may_hide(p, e.polygon(), i, t)
            })
    }
}
