//! Inside/outside-beam test for points.

use super::beam::NonlinearBeam;
use super::parameterization::Interpolant;
use super::projection::{BARY_TOLERANCE, s1_solutions};
use glam::Vec3;

impl<L: Interpolant> NonlinearBeam<L> {
    /// True when `q` lies in the beam: some projection has barycentric coordinates in the base
    /// triangle and `t ≥ 0`. The beam's side faces are the surfaces swept by the base edges (bilinear
    /// patches `(1 − s)(Pⱼ + t dⱼ) + s(Pₖ + t dₖ)` for S1); a barycentric coordinate of the projection
    /// changes sign exactly when `q` crosses one, so this is the side-surface test of 000 §6.1 solved
    /// through the projection cubic instead of a ray–patch intersection.
    #[must_use]
    pub fn contains(&self, q: Vec3) -> bool {
        self.project(q).iter().any(|p| p.t >= 0.0)
    }

    /// [`NonlinearBeam::contains`] for the S1 beam through the same boundary rays (one cubic; used to
    /// classify the brute-force case of Alg. 3 and 4 quickly).
    #[must_use]
    pub fn contains_s1(&self, q: Vec3) -> bool {
        let (sol, n) = s1_solutions(self.base.map(|v| v.as_dvec3()), self.dirs.map(|v| v.as_dvec3()), q.as_dvec3());
        sol[..n].iter().any(|&(w, t)| t >= 0.0 && w.min_element() >= -f64::from(BARY_TOLERANCE))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        let beam = NonlinearBeam::s1(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::new(-0.5, -0.5, 1.0), Vec3::new(0.5, 0.0, 1.0), Vec3::new(0.0, 0.5, 1.0)],
        )
        .unwrap();
        // The cross-section at height 2 spans roughly x, y ∈ [−1, 2].
        assert!(beam.contains(Vec3::new(0.2, 0.2, 2.0)));
        assert!(beam.contains(Vec3::new(-0.8, -0.8, 2.0)));
        assert!(!beam.contains(Vec3::new(-0.8, -0.8, 0.5)));
        assert!(!beam.contains(Vec3::new(0.2, 0.2, -1.0)));
        assert_eq!(beam.contains(Vec3::new(0.2, 0.2, 2.0)), beam.contains_s1(Vec3::new(0.2, 0.2, 2.0)));
    }
}
