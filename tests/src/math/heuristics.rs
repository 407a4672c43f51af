//! BVH cost-model areas (004).

use crate::generate::{self, uniform};
use crate::property::{Backend, Config, Outcome};
use beam_math::Ray;
use beam_math::collide::ray_aabb;
use beam_math::heuristics::{
    projected_area_orthographic, projected_area_orthographic_fast, projected_area_perspective,
    projected_area_perspective_fast,
};

/// Projected areas of boxes: orthographic hull area (and the builders' fast form) equals the closed form
/// `|d·x|·A_yz + |d·y|·A_xz + |d·z|·A_xy` (2,000 boxes); perspective hull area equals a Monte-Carlo
/// estimate of the box's image on the unit plane (eye rays through random image points hitting the
/// box) within 4σ, and the builders' front-face sum equals the hull area (1,000 boxes, 20,000 rays
/// each).
pub(super) fn projected_area_vs_sampling(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(17);
    for i in 0..2_000 {
        let b = generate::aabb(&mut rng, 2.0);
        let d = generate::unit(&mut rng);
        let e = b.extent();
        let closed = d.x.abs() * e.y * e.z + d.y.abs() * e.x * e.z + d.z.abs() * e.x * e.y;
        let hull = projected_area_orthographic(b, d);
        let fast = projected_area_orthographic_fast(b, d);
        if (hull - closed).abs() > 1e-4 * (1.0 + closed) || (fast - closed).abs() > 1e-4 * (1.0 + closed) {
            return Err(format!("case {i}: hull {hull}, fast {fast}, closed form {closed}"));
        }
    }
    let mut worst = 0.0f64;
    for i in 0..1_000 {
        let b = generate::aabb(&mut rng, 1.0);
        let eye = b.center() + generate::unit(&mut rng) * uniform(&mut rng, 2.5, 6.0);
        let forward = (b.center() - eye).normalize();
        let Some(area) = projected_area_perspective(b, eye, forward) else {
            continue;
        };
        let fast = projected_area_perspective_fast(b, eye, forward).unwrap_or(f32::NAN);
        if !((fast - area).abs() <= 1e-4 * area.max(1e-3)) {
            return Err(format!("case {i}: perspective hull area {area} vs front-face sum {fast}"));
        }
        let u = forward.any_orthonormal_vector();
        let v = forward.cross(u);
        // Sample a square twice as wide as the image's extent, so a too-small hull shows.
        let half = b
            .corners()
            .iter()
            .map(|c| {
                let r = *c - eye;
                (r.dot(u) / r.dot(forward)).abs().max((r.dot(v) / r.dot(forward)).abs())
            })
            .fold(0.0f32, f32::max)
            * 2.0;
        let samples = 20_000;
        let mut hits = 0;
        for _ in 0..samples {
            let p = eye + forward + u * uniform(&mut rng, -half, half) + v * uniform(&mut rng, -half, half);
            if ray_aabb(Ray::new(eye, p - eye), b).is_some() {
                hits += 1;
            }
        }
        let frac = f64::from(hits) / f64::from(samples);
        let square = f64::from(4.0 * half * half);
        let expected = f64::from(area) / square;
        let sigma = (expected * (1.0 - expected) / f64::from(samples)).sqrt().max(1.0 / f64::from(samples)) * square;
        let dev = (f64::from(area) - frac * square).abs() / sigma;
        worst = worst.max(dev);
        if dev > 4.0 {
            return Err(format!("case {i}: perspective area {area} vs Monte Carlo {}", frac * square));
        }
    }
    Ok(Outcome {
        cases: 3_000,
        note: format!("orthographic = closed form; perspective worst {worst:.2}σ from Monte Carlo"),
    })
}
