//! The CPU twin of the shading pass ([`shade_twin`]): the same estimator, the same jitter (the
//! shader's PCG hash of the point's seed), the same lights, so that GPU images can be held to a CPU
//! render pixel for pixel.

use super::{GpuLight, seed32};
use crate::interface::{LIGHT_POINT, LIGHT_TRIANGLE};
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::irradiance_map::IrradianceMap;
use beam_render::nonlinear::ShadePoint;
use beam_render::tolerance::{DEPTH_EPS, shading_eps};
use beam_scene::scene::{Material, Scene};

/// PCG hash (Jarzynski and Olano 2020), as in the shader.
fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A uniform number in `[0, 1)` from a seed and a sample index, as in the shader.
fn uniform01(seed: u32, i: u32) -> f32 {
    (pcg_hash(seed ^ pcg_hash(i)) >> 8) as f32 / 16_777_216.0
}

/// The CPU twin of the shader's `shade`: the radiance of point `s` (of a diffuse, glossy or emissive
/// triangle) with `spp` stratified shadow rays per area light, jittered exactly as the shader does.
#[must_use]
pub fn shade_twin(scene: &Scene, caustics: Option<&IrradianceMap>, spp: u32, s: &ShadePoint) -> Vec3 {
    let albedo = match scene.material(s.prim) {
        Material::Emissive { radiance } => return radiance,
        Material::Diffuse { albedo } | Material::Glossy { albedo, .. } => albedo,
        _ => return Vec3::ZERO,
    };
    let mut n = scene.normal(s.prim);
    if n.dot(s.d) >= 0.0 {
        n = -n;
    }
    let q = s.p + n * shading_eps(scene);
    let seed = seed32(s.seed);
    let occluded = |to: Vec3| scene.wide.any_hit(Ray::new(q, to), 1.0 - DEPTH_EPS);
    let mut e = Vec3::ZERO;
    for (j, light) in scene.lights.iter().enumerate() {
        let l = GpuLight::new(light);
        let (a, b, c) = (Vec3::from(l.a), Vec3::from(l.b), Vec3::from(l.c));
        if l.kind == LIGHT_POINT {
            let to = a - q;
            let r2 = to.dot(to);
            let cosine = n.dot(to) / r2.sqrt();
            if cosine > 0.0 && !occluded(to) {
                e += Vec3::from(l.power) * cosine / r2;
            }
            continue;
        }
        let ln = b.cross(c).normalize();
        let center = if l.kind == LIGHT_TRIANGLE { a + (b + c) / 3.0 } else { a + 0.5 * (b + c) };
        if ln.dot(q - center) <= 0.0 {
            continue;
        }
        let light_seed = pcg_hash(seed ^ pcg_hash(0x9e37_79b9_u32.wrapping_add(j as u32)));
        let spp = spp.max(1);
        let k = (spp as f32).sqrt() as u32;
        let mut integral = 0.0;
        for i in 0..spp {
            let (mut u, mut v) = (uniform01(light_seed, 2 * i), uniform01(light_seed, 2 * i + 1));
            if i < k * k {
                u = ((i % k) as f32 + u) / k as f32;
                v = ((i / k) as f32 + v) / k as f32;
            }
            if l.kind == LIGHT_TRIANGLE && u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let to = a + u * b + v * c - q;
            if occluded(to) {
                continue;
            }
            let r2 = to.dot(to);
            let w = to / r2.sqrt();
            integral += n.dot(w).max(0.0) * (-ln.dot(w)).max(0.0) / r2;
        }
        e += Vec3::from(l.power) * (l.area * integral / spp as f32);
    }
    if let Some(map) = caustics {
        e += map.irradiance(s.prim, s.p, s.d);
    }
    albedo / std::f32::consts::PI * e
}
