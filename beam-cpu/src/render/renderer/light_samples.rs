//! Where a shade point's shadow rays go: stratified samples of the unit square, their points on an
//! area light and the light's irradiance integrand there, a point light's one ray, and the
//! cosine-weighted directions that sample the environment's light.

use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_scene::scene::Light;
use rand::Rng;
use rand_pcg::Pcg32;

/// Sample `i` of `spp` on the unit square: jittered in the cells of the largest `k × k` grid with
/// `k² ≤ spp`, uniform past them.
pub(crate) fn light_sample(i: u32, spp: u32, rng: &mut Pcg32) -> (f32, f32) {
    let k = grid_side(spp);
    if i < k * k {
        (((i % k) as f32 + rng.random::<f32>()) / k as f32, ((i / k) as f32 + rng.random::<f32>()) / k as f32)
    } else {
        (rng.random::<f32>(), rng.random::<f32>())
    }
}

/// The side `k` of [`light_sample`]'s grid of `spp` samples: the largest with `k² ≤ spp`.
pub(super) fn grid_side(spp: u32) -> u32 {
    (spp as f32).sqrt() as u32
}

/// A point on an area light from `(s, t) ∈ [0, 1)²` (uniform in area).
pub(super) fn sample_light(light: &Light, s: f32, t: f32) -> Vec3 {
    match *light {
        Light::Quad { corner, edge_u, edge_v, .. } => corner + s * edge_u + t * edge_v,
        Light::Triangle { v, .. } => {
            let (s, t) = if s + t > 1.0 { (1.0 - s, 1.0 - t) } else { (s, t) };
            v[0] + s * (v[1] - v[0]) + t * (v[2] - v[0])
        }
        Light::Point { position, .. } => position,
    }
}

/// The irradiance integrand `cos θ cos θ′ / r²` at a point of normal `n` of the point `to` away
/// from it on an area light of unit normal `ln`.
pub(super) fn light_integrand(n: Vec3, ln: Vec3, to: Vec3) -> f32 {
    let r2 = to.length_squared();
    let w = to / r2.sqrt();
    n.dot(w).max(0.0) * (-ln).dot(w).max(0.0) / r2
}

/// The shadow ray from `p` (normal `n`) to a point light at `position` of intensity `intensity`
/// (unit parameter at the light) and the irradiance it gives `p` unoccluded; `None` where the
/// light is not above `p`'s tangent plane.
pub(super) fn point_light(p: Vec3, n: Vec3, position: Vec3, intensity: Vec3) -> Option<(Ray, Vec3)> {
    let to = position - p;
    let r2 = to.length_squared();
    let cos = n.dot(to) / r2.sqrt();
    (cos > 0.0).then(|| (Ray::new(p, to), intensity * cos / r2))
}

/// Two unit vectors that make a right-handed orthonormal frame with the unit vector `n` (Duff et
/// al. 2017, "Building an orthonormal basis, revisited").
pub(crate) fn tangents(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// The cosine-weighted direction about `n` of the frame `(u, v, n)` ([`tangents`]) for the point
/// `(s, r)` of the unit square, by Malley's method: uniform on the unit disc, lifted to the
/// hemisphere.
pub(crate) fn cosine_direction((u, v, n): (Vec3, Vec3, Vec3), (s, r): (f32, f32)) -> Vec3 {
    let (sin_phi, cos_phi) = (std::f32::consts::TAU * s).sin_cos();
    let radius = r.sqrt();
    radius * cos_phi * u + radius * sin_phi * v + (1.0 - r).max(0.0).sqrt() * n
}
