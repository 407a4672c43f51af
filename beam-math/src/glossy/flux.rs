//! Specular light beams of 002 §3: a scatterer triangle with three scattered rays, the flux plane
//! and flux triangle at a receiver fragment, the in-beam test and the specular irradiance (eq. 1).

use crate::collide::line_plane;
use crate::float::Float;
use crate::shapes::{Plane, Ray, Triangle};
use glam::Vec3;

/// A scattered (reflected or refracted) polygon beam, or a negative shadow beam: the scatterer
/// triangle's vertices, the three scattered unit directions and the flux it carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBeam {
    /// Scatterer vertices `A_W, B_W, C_W`.
    pub origins: [Vec3; 3],
    /// Unit scattered directions at the vertices (the triplet of 002 §3).
    pub dirs: [Vec3; 3],
    /// Beam flux `Φs = I_light·Ω_light` (negative for a shadow beam).
    pub flux: f32,
}

impl LightBeam {
    /// The flux plane through the fragment `f`: perpendicular to the average wavefront normal
    /// (the normalised sum of the scattered directions) (002 §3.1, Fig. 5).
    #[must_use]
    pub fn flux_plane(&self, f: Vec3) -> Option<Plane> {
        let n = (self.dirs[0] + self.dirs[1] + self.dirs[2]).try_normalize()?;
        Some(Plane::from_point_normal(f, n))
    }

    /// The flux triangle `A_F B_F C_F`: the scattered rays (as lines) meet the flux plane.
    #[must_use]
    pub fn flux_triangle(&self, plane: Plane) -> Option<Triangle> {
        let mut v = [Vec3::ZERO; 3];
        for i in 0..3 {
            let ray = Ray::new(self.origins[i], self.dirs[i]);
            v[i] = ray.at(line_plane(ray, plane)?);
        }
        Some(Triangle { v })
    }

    /// Specular irradiance at fragment `f` with unit normal `normal` (002 eq. 1):
    /// `E = Φs/A⊥ · cos θ` inside the beam, 0 outside; `A⊥` the flux-triangle area, `θ` between the
    /// normal and the incoming wavefront direction. Fragments behind the scatterer get nothing.
    #[must_use]
    pub fn specular_irradiance(&self, f: Vec3, normal: Vec3) -> f32 {
        let Some(plane) = self.flux_plane(f) else {
            return 0.0;
        };
        let Some(tri) = self.flux_triangle(plane) else {
            return 0.0;
        };
        if !self.in_front(f) || !in_beam(&tri, f) {
            return 0.0;
        }
        specular_irradiance(self.flux, tri.area(), (-plane.normal).dot(normal).max(0.0))
    }

    /// True when `f` lies downstream of the scatterer: strictly on the side of its plane that the
    /// scattered rays leave to (their mean direction's side). Points beside a scatterer whose flux
    /// plane cuts it (a receiver touching the scatterer's edge) count, which a test of the three
    /// rays' parameters at the flux plane would miss.
    #[must_use]
    pub fn in_front(&self, f: Vec3) -> bool {
        let n = (self.origins[1] - self.origins[0]).cross(self.origins[2] - self.origins[0]);
        let side = (self.dirs[0] + self.dirs[1] + self.dirs[2]).dot(n);
        side != 0.0 && (f - self.origins[0]).dot(n) * side > 0.0
    }
}

/// In-beam test: the fragment lies in the flux triangle (barycentric coordinates all `≥ 0`).
#[must_use]
pub fn in_beam(flux_triangle: &Triangle, f: Vec3) -> bool {
    flux_triangle.barycentric(f).is_some_and(|w| w.min_element() >= 0.0)
}

/// `E = Φs/A⊥ · cos θ` (002 eq. 1).
#[must_use]
pub fn specular_irradiance(flux: f32, area_perp: f32, cos_theta: f32) -> f32 {
    if area_perp > 0.0 { flux / area_perp * cos_theta } else { 0.0 }
}

/// Solid angle of a triangle seen from `eye` (Van Oosterom and Strackee), for `Ω_light` in
/// `Φs = I_light·Ω_light` (002 §4.1).
#[must_use]
pub fn solid_angle(eye: Vec3, tri: &Triangle) -> f32 {
    let [a, b, c] = tri.v.map(|v| v - eye);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2_(den).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_beam_irradiance() {
        // A beam falling straight down through a unit right triangle: flux 1 over area 0.5.
        let beam = LightBeam {
            origins: [Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 1.0, 2.0)],
            dirs: [-Vec3::Z; 3],
            flux: 1.0,
        };
        let e = beam.specular_irradiance(Vec3::new(0.2, 0.2, 0.0), Vec3::Z);
        assert!((e - 2.0).abs() < 1e-5);
        assert_eq!(beam.specular_irradiance(Vec3::new(0.8, 0.8, 0.0), Vec3::Z), 0.0);
        assert_eq!(beam.specular_irradiance(Vec3::new(0.2, 0.2, 3.0), Vec3::Z), 0.0);
    }

    #[test]
    fn solid_angle_of_an_octant() {
        let tri = Triangle::new(Vec3::X, Vec3::Y, Vec3::Z);
        assert!((solid_angle(Vec3::ZERO, &tri) - core::f32::consts::FRAC_PI_2).abs() < 1e-5);
    }
}
