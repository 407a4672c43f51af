//! Irradiance from a uniformly emitting polygon: Lambert's formula, and the point-source
//! approximation of 001 eq. 2.

use beam_math::glam::{DVec3, Vec3};

/// Clip a polygon to the half-space `n·(x − p) ≥ 0` (the hemisphere above a surface point).
#[must_use]
pub fn clip_above(polygon: &[Vec3], p: Vec3, n: Vec3) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for i in 0..polygon.len() {
        let a = polygon[i];
        let b = polygon[(i + 1) % polygon.len()];
        let (da, db) = (n.dot(a - p), n.dot(b - p));
        if da >= 0.0 {
            out.push(a);
        }
        if (da < 0.0) != (db < 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
    }
    out
}

/// Irradiance at `p` with unit normal `n` from a polygon of unit radiance, by Lambert's formula
/// `E = ½ Σᵢ Θᵢ (n · γ̂ᵢ)`, where `Θᵢ` is the angle the edge `i` subtends at `p` and `γ̂ᵢ` the unit
/// normal of the plane through `p` and the edge. The part of the polygon below the tangent plane is
/// clipped away first. Exact for the exact irradiance integral of 001 eq. 1 with a Lambertian BRDF.
#[must_use]
pub fn polygon_irradiance(p: Vec3, n: Vec3, polygon: &[Vec3]) -> f32 {
    // Lambert's sum over the edges of `clip_above`'s polygon, its corners taken as they come, in
    // double precision: the edges' terms are each about the light's angular size θ while their sum
    // is about θ², so in f32 a light 1% of the scene across kept only two or three digits.
    let (pd, nd) = (p.as_dvec3(), n.as_dvec3());
    let (mut first, mut last, mut corners, mut sum) = (DVec3::ZERO, DVec3::ZERO, 0usize, 0.0f64);
    let mut corner = |v: Vec3| {
        let v = v.as_dvec3();
        if corners == 0 {
            first = v;
        } else {
            sum += edge_irradiance_f64(pd, nd, last, v);
        }
        last = v;
        corners += 1;
    };
    for i in 0..polygon.len() {
        let a = polygon[i];
        let b = polygon[(i + 1) % polygon.len()];
        let (da, db) = (n.dot(a - p), n.dot(b - p));
        if da >= 0.0 {
            corner(a);
        }
        if (da < 0.0) != (db < 0.0) {
            corner(a + (b - a) * (da / (da - db)));
        }
    }
    if corners < 3 {
        return 0.0;
    }
    (sum + edge_irradiance_f64(pd, nd, last, first)).abs() as f32
}

/// One edge's term `½ Θ (n · γ̂)` of Lambert's formula ([`polygon_irradiance`]), signed, in double
/// precision: summed over the directed boundary of a region above the tangent plane (several loops,
/// holes), it gives the region's irradiance, positive for loops that turn counter-clockwise about
/// `(a − p) × (b − p)`'s direction away from `p`. The terms of many short edges largely cancel.
/// `atan2` keeps small angles accurate where `acos` of a dot product near 1 does not.
#[must_use]
#[inline]
pub(super) fn edge_irradiance_f64(p: DVec3, n: DVec3, a: DVec3, b: DVec3) -> f64 {
    let a = (a - p).normalize_or_zero();
    let b = (b - p).normalize_or_zero();
    let c = a.cross(b);
    let len = c.length();
    if len > 0.0 { 0.5 * len.atan2(a.dot(b)) * n.dot(c / len) } else { 0.0 }
}

/// 001 eq. 2: the irradiance of a point source at the light's centre, `A·cos θᵢ·cos θ_l / r²`, times
/// the fraction `visible` of the light seen from `p` (per unit radiance).
#[must_use]
pub fn point_source_irradiance(p: Vec3, n: Vec3, center: Vec3, light_normal: Vec3, area: f32, visible: f32) -> f32 {
    let d = center - p;
    let r2 = d.length_squared();
    if r2 == 0.0 {
        return 0.0;
    }
    let w = d / r2.sqrt();
    let cos_i = n.dot(w).max(0.0);
    let cos_l = (-light_normal).dot(w).max(0.0);
    area * cos_i * cos_l / r2 * visible
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_matches_the_disk_like_closed_form_and_far_field() {
        // A large square straight above: E → π (the whole hemisphere) as it grows.
        let big = [
            Vec3::new(-1e4, -1e4, 1.0),
            Vec3::new(1e4, -1e4, 1.0),
            Vec3::new(1e4, 1e4, 1.0),
            Vec3::new(-1e4, 1e4, 1.0),
        ];
        assert!((polygon_irradiance(Vec3::ZERO, Vec3::Z, &big) - std::f32::consts::PI).abs() < 1e-3);
        // A small square far away: E ≈ A cos / r².
        let s = 0.01;
        let small = [Vec3::new(-s, -s, 10.0), Vec3::new(s, -s, 10.0), Vec3::new(s, s, 10.0), Vec3::new(-s, s, 10.0)];
        let e = polygon_irradiance(Vec3::ZERO, Vec3::Z, &small);
        let approx =
            point_source_irradiance(Vec3::ZERO, Vec3::Z, Vec3::new(0.0, 0.0, 10.0), -Vec3::Z, 4.0 * s * s, 1.0);
        assert!((e - approx).abs() < 1e-3 * approx, "{e} vs {approx}");
        // Entirely below the horizon: nothing.
        let below: Vec<Vec3> = small.iter().map(|v| *v * Vec3::new(1.0, 1.0, -1.0)).collect();
        assert_eq!(polygon_irradiance(Vec3::ZERO, Vec3::Z, &below), 0.0);
    }
}
