//! The threshold plane `Π_T = Πa(t_res)` (000 §5, §6.2, App. B.2): above it every point has at most
//! one projection in the base triangle.

use super::NonlinearBeam;
use super::parameterization::Interpolant;
use crate::collide::triangle_triangle_distance;
use crate::roots::quadratic;
use crate::shapes::{Plane, Triangle};

/// The threshold plane of a beam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThresholdPlane {
    /// `t_max = max(0, 𝔖)`, `𝔖` the real roots of `f1, f2, f3`.
    pub t_max: f32,
    /// `t_res > t_max` with `min ‖P_res − P_max‖ > μ_b + t_max·μ_d` between `Δa(t_res)` and `Δa(t_max)`.
    pub t_res: f32,
    /// `Πa(t_res)`, oriented so that the beam directions point to its positive side.
    pub plane: Plane,
}

impl ThresholdPlane {
    /// True when every point of `tri` is strictly above the plane (000 Alg. 3: "Δ above Π_T").
    #[must_use]
    pub fn is_below(&self, tri: &Triangle) -> bool {
        !tri.v.iter().all(|&q| self.plane.eval(q) > 0.0)
    }
}

impl<L: Interpolant> NonlinearBeam<L> {
    /// The quadratics `fᵢ(t) = (P_{2,t} − P_{1,t}) × (P_{3,t} − P_{1,t}) · dᵢ` of 000 §5 as
    /// `(a, b, c)` with `fᵢ = a t² + b t + c`; by the cyclic symmetry of the triple product all three
    /// share the normal `N(t)` of `Δa(t)`.
    #[must_use]
    pub fn threshold_quadratics(&self) -> [[f64; 3]; 3] {
        let p = self.base.map(|v| v.as_dvec3());
        let d = self.dirs.map(|v| v.as_dvec3());
        let (e1, e2, f1, f2) = (p[1] - p[0], p[2] - p[0], d[1] - d[0], d[2] - d[0]);
        let n0 = e1.cross(e2);
        let n1 = e1.cross(f2) + f1.cross(e2);
        let n2 = f1.cross(f2);
        d.map(|di| [n2.dot(di), n1.dot(di), n0.dot(di)])
    }

    /// The threshold plane (000 §5; with the S^n condition of §6.2). `t_max` from the roots of the
    /// three quadratics; `t_res` by doubling a step above `t_max` until the distance between
    /// `Δa(t_res)` and `Δa(t_max)` exceeds `μ_b + t_max·μ_d` (and a small fraction of the base size,
    /// so that the strict `> 0` of S1 is robust in floating point).
    #[must_use]
    pub fn threshold_plane(&self) -> ThresholdPlane {
        let mut t_max = 0.0f64;
        for [a, b, c] in self.threshold_quadratics() {
            for &t in quadratic(a, b, c).as_slice() {
                t_max = t_max.max(t);
            }
        }
        let t_max = t_max as f32;
        let (mu_b, mu_d) = self.max_offsets();
        let size = self.base.iter().fold(0.0f32, |m, p| m.max(p.distance(self.base[0])));
        let margin = (mu_b + t_max * mu_d).max(1e-4 * size);
        let low = self.affine_triangle(t_max);
        let mut step = 1e-3 * size.max(t_max * 1e-3);
        let mut t_res = f32::INFINITY;
        for _ in 0..64 {
            let t = t_max + step;
            if triangle_triangle_distance(&self.affine_triangle(t), &low) > margin {
                t_res = t;
                break;
            }
            step *= 2.0;
        }
        let plane = if t_res.is_finite() { self.affine_plane(t_res) } else { self.affine_plane(t_max) };
        let facing = self.dirs.iter().map(|d| plane.normal.dot(*d)).sum::<f32>();
        let plane = if facing < 0.0 { Plane { normal: -plane.normal, d: -plane.d } } else { plane };
        ThresholdPlane { t_max, t_res, plane }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn diverging_beam_threshold_is_near_the_base() {
        let beam = NonlinearBeam::s1(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::new(-0.3, -0.3, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)],
        )
        .unwrap();
        let th = beam.threshold_plane();
        assert_eq!(th.t_max, 0.0);
        assert!(th.t_res > 0.0 && th.t_res < 0.1, "{th:?}");
    }

    #[test]
    fn converging_beam_threshold_is_past_the_focus() {
        // Rays aimed at (1/3, 1/3, 2): the affine triangle collapses at t ≈ 2.
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let focus = Vec3::new(1.0 / 3.0, 1.0 / 3.0, 2.0);
        let beam = NonlinearBeam::s1(base, base.map(|p| focus - p)).unwrap();
        let th = beam.threshold_plane();
        assert!(th.t_max > 1.9 && th.t_res > th.t_max, "{th:?}");
        // A point just beyond the focus is above, the base itself is below.
        assert!(th.is_below(&beam.base_triangle()));
    }
}
