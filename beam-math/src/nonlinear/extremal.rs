//! Extremal directions `{d̂1, d̂2, d̂3}` (000 §6.2): directions at the base vertices whose cone
//! contains every interior ray direction `d(P)`.

use super::beam::NonlinearBeam;
use super::bounding_triangle::enclosing_triangle;
use super::parameterization::Interpolant;
use crate::shapes::Triangle;
use glam::{Vec2, Vec3};

impl<L: Interpolant> NonlinearBeam<L> {
    /// Extremal directions (000 §6.2), unit length. Every `d(P)` is a non-negative combination of
    /// the direction control points (convex-hull property), so it suffices to contain those. In the
    /// base frame each control point `(x, y, z)` is centrally projected to `(x/z, y/z)` on the plane
    /// `z = 1`; the triangle of the projected `dᵢ` is widened with its edges kept parallel until it
    /// contains them all, and its corners lifted back give `d̂ᵢ`. For S1 this returns `dᵢ` itself.
    #[must_use]
    pub fn extremal_directions(&self) -> [Vec3; 3] {
        let p = &self.patch;
        if p.degree == 1 {
            return self.dirs;
        }
        let n = self.normal;
        let u = (self.base[1] - self.base[0]).normalize();
        let v = n.cross(u);
        let flat = |d: Vec3| {
            let z = d.dot(n).max(0.5 * super::beam::MIN_ELEVATION);
            Vec2::new(d.dot(u) / z, d.dot(v) / z)
        };
        let lift = |q: Vec2| (q.x * u + q.y * v + n).normalize();
        let to3 = |q: Vec2| Vec3::new(q.x, q.y, 0.0);
        let reference = Triangle { v: self.dirs.map(|d| to3(flat(d))) };
        // A degenerate direction triangle (nearly parallel rays): use the shape of the base instead.
        let reference = if reference.area() > 1e-8 {
            reference
        } else {
            let c = (reference.v[0] + reference.v[1] + reference.v[2]) / 3.0;
            let b = self.base.map(|x| to3(Vec2::new(x.dot(u), x.dot(v))));
            let bc = (b[0] + b[1] + b[2]) / 3.0;
            Triangle { v: b.map(|x| c + (x - bc) * 1e-3) }
        };
        let bary = (0..p.count).filter_map(|i| reference.barycentric(to3(flat(p.direction[i].as_vec3()))));
        let corners = enclosing_triangle(bary, Vec3::ZERO);
        corners.map(|w| lift(reference.point(w).truncate()))
    }
}

#[cfg(test)]
mod tests {
    use super::super::parameterization::S3;
    use super::*;

    #[test]
    fn s3_directions_are_inside_the_extremal_cone() {
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let dirs = [Vec3::new(-0.2, -0.2, 1.0), Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.0, 0.3, 1.0)];
        let normals = [
            Vec3::new(-0.4, -0.4, 1.0).normalize(),
            Vec3::new(0.5, 0.0, 1.0).normalize(),
            Vec3::new(0.0, 0.5, 1.0).normalize(),
        ];
        let beam = NonlinearBeam::new(base, dirs, S3 { normals }).unwrap();
        let e = beam.extremal_directions();
        let m = glam::Mat3::from_cols(e[0], e[1], e[2]).inverse();
        for i in 0..=12 {
            for j in 0..=12 - i {
                let w = Vec3::new(i as f32, j as f32, (12 - i - j) as f32) / 12.0;
                let coeffs = m * beam.ray_at(w).direction;
                assert!(coeffs.min_element() >= -1e-5, "{w} → {coeffs}");
            }
        }
        let s1 = NonlinearBeam::s1(base, dirs).unwrap();
        assert_eq!(s1.extremal_directions(), s1.dirs);
    }
}
