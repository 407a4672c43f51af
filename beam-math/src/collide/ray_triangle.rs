//! Watertight ray–triangle intersection (Woop, Benthin, Wald 2013), the closest-hit primitive of
//! 004 App. A.3 made exact on shared edges: no ray passes between two triangles that share an edge.

use crate::shapes::{Ray, Triangle};
use glam::{Mat3A, Vec3, Vec3A};

/// A ray–triangle hit: the ray parameter and the barycentric coordinates of the hit point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter `t` of the hit point.
    pub t: f32,
    /// Barycentric weight of vertex 1.
    pub u: f32,
    /// Barycentric weight of vertex 2 (vertex 0 has `1 − u − v`).
    pub v: f32,
}

/// Per-ray constants of the watertight test: the axis permutation (largest |d| becomes z, winding
/// kept) and the shear, folded into one matrix so that a vertex is transformed without branches:
/// rows `e_kx − Sx·e_kz`, `e_ky − Sy·e_kz`, `Sz·e_kz`.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3A,
    shear: Mat3A,
}

impl WatertightRay {
    /// Precompute the permutation and shear of `ray`.
    #[must_use]
    pub fn new(ray: Ray) -> Self {
        let d = ray.direction;
        let a = d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            core::mem::swap(&mut kx, &mut ky);
        }
        let (sx, sy, sz) = (d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        let unit = |k: usize| Vec3A::from(Vec3::AXES[k]);
        let rows = [unit(kx) - sx * unit(kz), unit(ky) - sy * unit(kz), sz * unit(kz)];
        Self { origin: ray.origin.into(), shear: Mat3A::from_cols(rows[0], rows[1], rows[2]).transpose() }
    }

    /// Intersect one triangle; hits with `t` in `[t_min, t_max]` are returned. Both faces count.
    #[must_use]
    #[inline]
    pub fn intersect(&self, tri: &Triangle, t_min: f32, t_max: f32) -> Option<TriangleHit> {
        let a = self.shear * (Vec3A::from(tri.v[0]) - self.origin);
        let b = self.shear * (Vec3A::from(tri.v[1]) - self.origin);
        let c = self.shear * (Vec3A::from(tri.v[2]) - self.origin);
        let mut u = c.x * b.y - c.y * b.x;
        let mut v = a.x * c.y - a.y * c.x;
        let mut w = b.x * a.y - b.y * a.x;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            // Fall back to double precision on the edges, as the paper prescribes.
            let f = |px: f32, py: f32, qx: f32, qy: f32| (px as f64 * qy as f64 - py as f64 * qx as f64) as f32;
            u = f(c.x, c.y, b.x, b.y);
            v = f(a.x, a.y, c.x, c.y);
            w = f(b.x, b.y, a.x, a.y);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let t_scaled = u * a.z + v * b.z + w * c.z;
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        if !(t >= t_min && t <= t_max) {
            return None;
        }
        // u, v, w weight vertices 0, 1, 2.
        Some(TriangleHit { t, u: v * inv, v: w * inv })
    }
}

/// Watertight ray–triangle intersection for hits with `t ≥ 0`.
#[must_use]
pub fn ray_triangle(ray: Ray, tri: &Triangle) -> Option<TriangleHit> {
    WatertightRay::new(ray).intersect(tri, 0.0, f32::INFINITY)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked_hit() {
        let tri = Triangle::new(Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 1.0, 2.0));
        let h = ray_triangle(Ray::new(Vec3::new(0.25, 0.25, 0.0), Vec3::Z), &tri).unwrap();
        assert!((h.t - 2.0).abs() < 1e-6);
        assert!((h.u - 0.25).abs() < 1e-6 && (h.v - 0.25).abs() < 1e-6);
        let p = tri.point(Vec3::new(1.0 - h.u - h.v, h.u, h.v));
        assert!((p - Vec3::new(0.25, 0.25, 2.0)).length() < 1e-6);
        assert!(ray_triangle(Ray::new(Vec3::new(0.75, 0.75, 0.0), Vec3::Z), &tri).is_none());
        assert!(ray_triangle(Ray::new(Vec3::new(0.25, 0.25, 3.0), Vec3::Z), &tri).is_none());
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of a quad; rays exactly on the diagonal hit at least one.
        let a = Vec3::new(0.0, 0.0, 1.0);
        let b = Vec3::new(1.0, 0.0, 1.0);
        let c = Vec3::new(1.0, 1.0, 1.0);
        let d = Vec3::new(0.0, 1.0, 1.0);
        let t1 = Triangle::new(a, b, c);
        let t2 = Triangle::new(a, c, d);
        let eye = Vec3::new(0.3, 0.1, -0.7);
        for i in 1..1000 {
            let s = i as f32 / 1000.0;
            let target = a + s * (c - a);
            let ray = Ray::new(eye, target - eye);
            assert!(ray_triangle(ray, &t1).is_some() || ray_triangle(ray, &t2).is_some(), "crack at {s}");
        }
    }

    #[test]
    fn degenerate_triangle_never_hits() {
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, 2.0 * Vec3::X);
        assert!(ray_triangle(Ray::new(Vec3::new(0.5, 0.0, -1.0), Vec3::Z), &tri).is_none());
    }
}
