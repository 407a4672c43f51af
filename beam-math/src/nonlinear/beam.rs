//! The nonlinear beam of 000 §4: a base triangle `ΔP1P2P3` with unit boundary directions
//! `{d1, d2, d3}` and an S^n parameterization of ray origins and directions over the base.

use super::parameterization::{Interpolant, MAX_DEGREE, Patch, S1};
use crate::float::Float;
use crate::shapes::{Plane, Ray, Triangle};
use glam::{DVec3, Vec3};

/// The smallest elevation `d·n` of a boundary direction above the base plane: 000 §4 clamps the
/// local z-component to `max(δ, d_z)` so that all rays leave the base on the same side.
pub const MIN_ELEVATION: f32 = 0.01;

/// A nonlinear beam (000 §4, Fig. 3a) with coefficient function `L` (default [`S1`]).
#[derive(Clone, Copy, Debug)]
pub struct NonlinearBeam<L: Interpolant = S1> {
    /// Base vertices `P1, P2, P3`.
    pub base: [Vec3; 3],
    /// Unit boundary directions `d1, d2, d3`, clamped to the inner side of the base plane.
    pub dirs: [Vec3; 3],
    /// Unit normal `n` of the base plane, facing the inside of the beam.
    pub normal: Vec3,
    /// The coefficient function `L_ijk` of eq. 1.
    pub interp: L,
    /// Bernstein control points of `O(ω)` and `d(ω)`.
    pub patch: Patch,
}

impl<L: Interpolant> NonlinearBeam<L> {
    /// A beam from its base, boundary directions and parameterization. The base normal is oriented
    /// towards the mean direction and every direction is normalised and clamped to an elevation of at
    /// least [`MIN_ELEVATION`] (000 §4). `None` for a degenerate base, zero or non-finite input,
    /// or a parameterization of degree 0 or above [`MAX_DEGREE`].
    #[must_use]
    pub fn new(base: [Vec3; 3], dirs: [Vec3; 3], interp: L) -> Option<Self> {
        if !(1..=MAX_DEGREE).contains(&interp.degree()) {
            return None;
        }
        let n = Triangle { v: base }.scaled_normal();
        let mean = dirs[0] + dirs[1] + dirs[2];
        if !n.is_finite() || !mean.is_finite() || base.iter().any(|p| !p.is_finite()) {
            return None;
        }
        let mut normal = n.try_normalize()?;
        if normal.dot(mean) < 0.0 {
            normal = -normal;
        }
        let mut clamped = [Vec3::ZERO; 3];
        for (c, d) in clamped.iter_mut().zip(dirs) {
            let d = d.try_normalize()?;
            let z = d.dot(normal);
            *c = if z >= MIN_ELEVATION {
                d
            } else {
                let tangent = (d - z * normal).normalize_or(normal.any_orthonormal_vector());
                tangent * (1.0 - MIN_ELEVATION * MIN_ELEVATION).sqrt_() + MIN_ELEVATION * normal
            };
        }
        let patch = Patch::new(&interp, &base, &clamped);
        Some(Self { base, dirs: clamped, normal, interp, patch })
    }

    /// The base triangle `Δb`.
    #[must_use]
    pub fn base_triangle(&self) -> Triangle {
        Triangle { v: self.base }
    }

    /// The base plane `Πb` with unit normal facing the inside of the beam.
    #[must_use]
    pub fn base_plane(&self) -> Plane {
        Plane::from_point_normal(self.base[0], self.normal)
    }

    /// Degree `n` of the parameterization.
    #[must_use]
    pub fn degree(&self) -> usize {
        self.patch.degree
    }

    /// The ray `(O_P, d_P)` of eq. 1 at barycentric coordinates `w` on the base (000 §5,
    /// *Intersection*). The direction is not normalised.
    #[must_use]
    pub fn ray_at(&self, w: Vec3) -> Ray {
        let (o, d) = self.patch.eval(w.as_dvec3());
        Ray::new(o.as_vec3(), d.as_vec3())
    }

    /// [`NonlinearBeam::ray_at`] in double precision.
    #[must_use]
    pub fn ray_at_f64(&self, w: DVec3) -> (DVec3, DVec3) {
        self.patch.eval(w)
    }

    /// Heights `h_k` of the base triangle (distance from `P_k` to the opposite edge): a distance `ε`
    /// across edge `k` is `ε/h_k` in barycentric coordinate `ω_k`.
    #[must_use]
    pub fn heights(&self) -> Vec3 {
        heights(&self.base_triangle())
    }
}

impl NonlinearBeam<S1> {
    /// An S1 beam (eq. 3).
    #[must_use]
    pub fn s1(base: [Vec3; 3], dirs: [Vec3; 3]) -> Option<Self> {
        Self::new(base, dirs, S1)
    }
}

/// Heights of a triangle from each vertex to the opposite edge.
#[must_use]
pub fn heights(tri: &Triangle) -> Vec3 {
    let twice_area = tri.scaled_normal().length();
    Vec3::from_array(core::array::from_fn(|k| twice_area / (tri.v[(k + 2) % 3] - tri.v[(k + 1) % 3]).length()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamps_grazing_directions() {
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let beam = NonlinearBeam::s1(base, [Vec3::Z, Vec3::new(1.0, 0.0, -0.2), Vec3::Z]).unwrap();
        assert_eq!(beam.normal, Vec3::Z);
        assert!((beam.dirs[1].z - MIN_ELEVATION).abs() < 1e-6);
        assert!((beam.dirs[1].length() - 1.0).abs() < 1e-6);
        assert!(NonlinearBeam::s1([Vec3::ZERO, Vec3::X, 2.0 * Vec3::X], [Vec3::Z; 3]).is_none());
    }

    /// A parameterization the patch cannot hold is refused, not evaluated at a lower degree.
    #[test]
    fn refuses_degrees_past_the_patch() {
        #[derive(Clone, Copy)]
        struct Quartic;
        impl Interpolant for Quartic {
            fn degree(&self) -> usize {
                MAX_DEGREE + 1
            }
            fn coefficient(&self, _: [usize; 3], x: &[Vec3; 3]) -> Vec3 {
                x[0]
            }
        }
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert!(NonlinearBeam::new(base, [Vec3::Z; 3], Quartic).is_none());
        assert!(NonlinearBeam::new(base, [Vec3::Z; 3], S1).is_some());
    }

    #[test]
    fn ray_at_vertices_and_heights() {
        let base = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)];
        let beam = NonlinearBeam::s1(base, [Vec3::Z; 3]).unwrap();
        let r = beam.ray_at(Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(r.origin, base[1]);
        let h = beam.heights();
        assert!((h.x - 2f32.sqrt()).abs() < 1e-6 && (h.y - 2.0).abs() < 1e-6 && (h.z - 2.0).abs() < 1e-6);
    }
}
