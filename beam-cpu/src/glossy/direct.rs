//! The ground truth of the emitters' direct light: shadow rays over each light's whole area; and
//! the environment's light, by cosine-weighted rays over the hemisphere.

use crate::render::renderer::light_samples::{cosine_direction, light_sample, tangents};
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::glossy::{REFERENCE_AREA_RAYS, area_point, whole};
use beam_render::tolerance::{DEPTH_EPS, shading_eps};
use beam_scene::scene::{Light, Scene};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// Direct irradiance at `p` (unit normal `n`, its cosines taken with the unit `shading` normal: a
/// normal texture's, else `n`) from every light of `scene` above the surface, every occluder
/// casting shadows: a point light by one shadow ray, an area light by [`REFERENCE_AREA_RAYS`]
/// stratified, jittered shadow rays over its area (seeded by `seed`), each weighted by the cosines
/// at both ends over the squared distance; plus the environment's ([`sky_irradiance`] by as many
/// rays). The ground truth of the emitters' direct light.
#[must_use]
pub fn reference_direct(scene: &Scene, p: Vec3, [n, shading]: [Vec3; 2], seed: u64) -> Vec3 {
    let eps = shading_eps(scene);
    let q = p + n * eps;
    let mut rng = Pcg32::seed_from_u64(seed);
    let k = (REFERENCE_AREA_RAYS as f32).sqrt() as u32;
    let mut e = Vec3::ZERO;
    for (i, light) in scene.lights.iter().enumerate() {
        let Some(whole) = whole(scene, light, i as u32) else { continue };
        let samples = if matches!(light, Light::Point { .. }) { 1 } else { k * k };
        // The occluder of the last ray to this light, tested first (the same answers, sooner).
        let mut last = None;
        for j in 0..samples {
            let x = if samples == 1 {
                whole.position
            } else {
                let (s, t) = ((j % k) as f32 + rng.random::<f32>(), (j / k) as f32 + rng.random::<f32>());
                area_point(light, s / k as f32, t / k as f32) + whole.normal * eps
            };
            let to = x - q;
            let r2 = to.length_squared();
            let d = to / r2.sqrt();
            let cos = shading.dot(d);
            let falloff = whole.falloff(-d);
            if !(n.dot(d) > 0.0 && cos > 0.0 && falloff > 0.0)
                || scene.occluded_after(Ray::new(q, to), 1.0 - DEPTH_EPS, &mut last)
            {
                continue;
            }
            e += whole.intensity * (falloff * cos / (r2 * samples as f32));
        }
    }
    e + sky_irradiance(scene, p, [n, shading], seed, REFERENCE_AREA_RAYS)
}

/// Rays a point of the glossy method's image gives the environment ([`sky_irradiance`]).
pub const SKY_RAYS: u32 = 64;

/// Irradiance at `p` (unit normal `n`, cosines with the unit `shading` normal) from `scene`'s
/// environment: `rays` stratified, jittered cosine-weighted directions about `shading` (the
/// renderer's light samples, seeded by `seed`), those above the surface (`n`) traced to infinity
/// past every occluder, each that leaves the scene bringing the environment's radiance from its
/// direction; the estimate `π/N Σ L(ωᵢ)` (the cosine and the density `cos θ / π` cancel), exact
/// for a constant sky over an open hemisphere. Zero, with no ray, under a black environment. Light
/// the environment sends by way of mirrors, glass or glossy surfaces is not gathered.
#[must_use]
pub fn sky_irradiance(scene: &Scene, p: Vec3, [n, shading]: [Vec3; 2], seed: u64, rays: u32) -> Vec3 {
    if scene.environment.is_black() {
        return Vec3::ZERO;
    }
    let q = p + n * shading_eps(scene);
    let mut rng = Pcg32::seed_from_u64(seed ^ 0x05ca_1ab1_e0dd_ba11);
    let (u, v) = tangents(shading);
    let rays = rays.max(1);
    let mut sum = Vec3::ZERO;
    let mut last = None;
    for i in 0..rays {
        let w = cosine_direction((u, v, shading), light_sample(i, rays, &mut rng));
        if n.dot(w) > 0.0 && !scene.occluded_after(Ray::new(q, w), f32::INFINITY, &mut last) {
            sum += scene.environment.radiance(w);
        }
    }
    core::f32::consts::PI * sum / rays as f32
}
