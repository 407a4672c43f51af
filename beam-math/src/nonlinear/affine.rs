//! Affine triangles and planes (000 §5, Fig. 5): `Δa(t)` with vertices `Hᵢ = Pᵢ + t·dᵢ`, and transfer.

use super::beam::NonlinearBeam;
use super::parameterization::Interpolant;
use crate::collide::line_plane;
use crate::shapes::{Plane, Ray, Triangle};
use glam::{DVec3, Vec3};

impl<L: Interpolant> NonlinearBeam<L> {
    /// The affine triangle `Δa(t)`: `Hᵢ = Pᵢ + t·dᵢ` (000 §5, Fig. 5).
    #[must_use]
    pub fn affine_triangle(&self, t: f32) -> Triangle {
        Triangle { v: core::array::from_fn(|i| self.base[i] + t * self.dirs[i]) }
    }

    /// The affine triangle in double precision.
    #[must_use]
    pub fn affine_triangle_f64(&self, t: f64) -> [DVec3; 3] {
        core::array::from_fn(|i| self.base[i].as_dvec3() + t * self.dirs[i].as_dvec3())
    }

    /// `±1`: the sign that turns `(P2 − P1) × (P3 − P1)` into the inner normal `n`.
    #[must_use]
    pub fn winding(&self) -> f32 {
        self.base_triangle().scaled_normal().dot(self.normal).signum()
    }

    /// The affine plane `Πa(t)` through `Δa(t)` with normal `±(H2 − H1) × (H3 − H1)`, the sign of
    /// [`NonlinearBeam::winding`] (so `Πa(0) = Πb` with the inner normal).
    #[must_use]
    pub fn affine_plane(&self, t: f32) -> Plane {
        let tri = self.affine_triangle(t);
        let n = tri.scaled_normal();
        Plane::from_point_normal(tri.v[0], self.winding() * n)
    }
}

/// Transfer of `q` on `plane` in direction `d` (000 §5, Fig. 3c): the point `H` of the plane with
/// `q = H + t·d`. `None` when `d` is parallel to the plane.
#[must_use]
pub fn transfer(q: Vec3, d: Vec3, plane: Plane) -> Option<Vec3> {
    line_plane(Ray::new(q, d), plane).map(|t| q + t * d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_hand_worked() {
        let plane = Plane::from_point_normal(Vec3::ZERO, Vec3::Z);
        let h = transfer(Vec3::new(1.0, 1.0, 2.0), Vec3::new(0.5, 0.0, 1.0), plane).unwrap();
        assert!((h - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-6);
        assert!(transfer(Vec3::ONE, Vec3::X, plane).is_none());
    }

    #[test]
    fn affine_triangle_moves_along_directions() {
        let beam =
            NonlinearBeam::s1([Vec3::ZERO, Vec3::X, Vec3::Y], [Vec3::Z, Vec3::new(1.0, 0.0, 1.0), Vec3::Z]).unwrap();
        let a = beam.affine_triangle(2.0);
        assert!((a.v[1] - (Vec3::X + 2.0 * beam.dirs[1])).length() < 1e-6);
        assert!(beam.affine_plane(0.0).normal.dot(Vec3::Z) > 0.0);
    }
}
