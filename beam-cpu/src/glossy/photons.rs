//! The Monte-Carlo ground truth of the light volumes: photons from each light through the scatterer
//! triangles (from a point light's position, or from a uniformly random point of an area light's
//! area, weighted by its cosine emission: the area itself, not the beams' strata), scattered about
//! the interpolated normal at their own point (Fresnel split for glass) and spread by the Gaussian
//! micro-facet model of 002 §4.2 (the scatter direction at a 2D Gaussian angular offset, standard
//! deviation σ, from the specular one), deposited on the first surface they reach when it is a
//! receiver. The light is checked for occlusion before the scatterer and so is the scattered
//! photon's path (second-order shadows, which the beams leave out).

use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_math::glossy::solid_angle;
use beam_render::glossy::{Scatter, area_point, scatterings, whole};
use beam_render::irradiance_map::IrradianceMap;
use beam_render::specular::{dielectric, reflect};
use beam_render::tolerance::{DEPTH_EPS, shading_eps};
use beam_scene::scene::{Light, Material, Scene};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// World size of the photon map's texels for `scene`: 1/512 of its bounding box's largest side.
#[must_use]
pub fn photon_texel(scene: &Scene) -> f32 {
    scene.bounds().extent().max_element() / 512.0
}

/// `d` turned by a 2D Gaussian angular offset of standard deviation `sigma` (radians).
fn spread(d: Vec3, sigma: f32, rng: &mut Pcg32) -> Vec3 {
    if sigma <= 0.0 {
        return d;
    }
    // Box–Muller: two independent normal deviates, the offset's components along two tangents.
    let (u1, u2): (f32, f32) = (rng.random::<f32>().max(f32::MIN_POSITIVE), rng.random());
    let r = sigma * (-2.0 * u1.ln()).sqrt();
    let (s, c) = (core::f32::consts::TAU * u2).sin_cos();
    let t1 = d.any_orthonormal_vector();
    let t2 = d.cross(t1);
    (d * r.cos() + (t1 * c + t2 * s) * r.sin()).normalize_or_zero()
}

/// About `photons` photons per light, spread over the scatterer triangles in proportion to the
/// solid angle they fill from the light's centre, uniformly over each triangle's area; each carries
/// `I·cosθ·A/(r²·M)` of its triangle's `M`. For an area light (radiance `L`, area `A_L`) each
/// photon leaves a uniformly random point of its area with `I = L·A_L·cosθ_L` towards the
/// triangle's point: the same light as the area emits, sampled by area at both ends. Returns the
/// irradiance map of the scattered light (texel [`photon_texel`]; a thin wall lit on one side stays
/// dark on the other).
#[must_use]
pub fn glossy_photons(scene: &Scene, photons: u64, seed: u64) -> IrradianceMap {
    let empty = IrradianceMap::new(scene, photon_texel(scene));
    let eps = shading_eps(scene);
    let mut jobs = Vec::new();
    for (li, source) in scene.lights.iter().enumerate() {
        let Some(emitter) = whole(scene, source, li as u32) else { continue };
        let light = emitter.position;
        let scatterers: Vec<(u32, f32)> = (0..scene.triangles.len() as u32)
            .filter(|&p| !scatterings(&scene.material(p)).is_empty())
            .map(|p| (p, solid_angle(light, &scene.triangles[p as usize])))
            .filter(|&(_, omega)| omega > 0.0 && omega.is_finite())
            .collect();
        let total: f32 = scatterers.iter().map(|s| s.1).sum();
        for &(prim, omega) in &scatterers {
            let m = (photons as f64 * f64::from(omega / total)).ceil() as u64;
            let seed = seed ^ (u64::from(prim) << 8 | li as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            jobs.push((source, emitter, prim, m, seed));
        }
    }
    // In a fixed order, so that every process of a render farm sums the same map.
    beam_render::ordered::fold_in_order(
        &jobs,
        || empty.clone(),
        |mut map, &(source, emitter, prim, m, seed)| {
            let mut rng = Pcg32::seed_from_u64(seed);
            let tri = scene.triangles[prim as usize];
            let (area, g) = (tri.area(), scene.normal(prim));
            let material = scene.material(prim);
            for _ in 0..m {
                let (mut s, mut t) = (rng.random::<f32>(), rng.random::<f32>());
                if s + t > 1.0 {
                    (s, t) = (1.0 - s, 1.0 - t);
                }
                let p = tri.v[0] * (1.0 - s - t) + tri.v[1] * s + tri.v[2] * t;
                let light = match source {
                    Light::Point { .. } => emitter.position,
                    _ => area_point(source, rng.random(), rng.random()) + emitter.normal * eps,
                };
                let to = p - light;
                let r2 = to.length_squared();
                let d = to / r2.sqrt();
                let front = g.dot(d) < 0.0;
                let side = if front { g } else { -g };
                let o = p + side * eps;
                if scene.occluded(Ray::new(light, o - light), 1.0 - DEPTH_EPS) {
                    continue;
                }
                if !front && !matches!(material, Material::ThinGlass { .. }) {
                    continue;
                }
                let n = scene.shading_normal(prim, p) * side.dot(g).signum();
                let flux = emitter.towards(d) * (g.dot(d).abs() * area / (r2 * m as f32));
                if flux == Vec3::ZERO {
                    continue;
                }
                for (scatter, tint, sigma) in scatterings(&material) {
                    let (weight, dir, origin) = match scatter {
                        Scatter::Reflect => {
                            let w = match material {
                                Material::Glass { ior } => dielectric(d, n, ior, true).0,
                                _ => 1.0,
                            };
                            (w, reflect(d, n), o)
                        }
                        Scatter::Refract { ior } => match dielectric(d, n, ior, true) {
                            (fresnel, Some(t)) => (1.0 - fresnel, t, p - side * eps),
                            (_, None) => (0.0, d, o),
                        },
                        Scatter::Transmit => (1.0, d, p - side * eps),
                    };
                    let dir = spread(dir.normalize_or_zero(), sigma, &mut rng);
                    if weight <= 0.0 || dir == Vec3::ZERO {
                        continue;
                    }
                    let ray = Ray::new(origin, dir);
                    if let Some(hit) = scene.closest_hit(ray, f32::INFINITY)
                        && !beam_render::glossy::is_scatterer(&scene.material(hit.prim))
                    {
                        map.splat(hit.prim, ray.at(hit.t), dir, flux * tint * weight);
                    }
                }
            }
            map
        },
        |a, b| a.merge(&b),
    )
}
