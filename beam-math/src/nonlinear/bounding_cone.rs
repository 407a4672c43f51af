//! Bounding cone of a beam (000 App. A, proof in App. B.7), for culling objects by their bounding
//! spheres with [`crate::collide::cone_sphere`].

use super::beam::NonlinearBeam;
use super::parameterization::Interpolant;
use crate::collide::Cone;
use crate::float::Float;
use glam::Vec3;

/// Smallest half-angle used, so that a beam of parallel rays gets a finite apex.
pub const MIN_CONE_ANGLE: f32 = 1e-3;

impl<L: Interpolant> NonlinearBeam<L> {
    /// The bounding cone of 000 App. A: `d_C = (d̂1 + d̂2 + d̂3)/‖·‖`,
    /// `θ_C = acos(min d̂ᵢ·d_C) + extra_angle`, `P_C = P_G − d_C · max‖O_P − P_G‖ / sin θ_C`.
    /// The maximum over the base is bounded by the origin control points (exact for S1).
    /// `extra_angle` widens the cone for perturbed (bump-mapped) rays by their maximum angle δ.
    #[must_use]
    pub fn bounding_cone(&self, extremal: &[Vec3; 3], extra_angle: f32) -> Cone {
        let axis = (extremal[0] + extremal[1] + extremal[2]).normalize_or(self.normal);
        let cos_min = extremal.iter().fold(1.0f32, |m, d| m.min(d.normalize().dot(axis)));
        let angle = (cos_min.clamp(-1.0, 1.0).acos_() + extra_angle).max(MIN_CONE_ANGLE);
        let centroid = (self.base[0] + self.base[1] + self.base[2]) / 3.0;
        let p = &self.patch;
        let reach = (0..p.count).fold(0.0f32, |m, i| m.max(p.origin[i].as_vec3().distance(centroid)));
        let apex = centroid - axis * (reach * 1.0001 / angle.sin_());
        Cone { apex, axis, angle }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_contains_sampled_beam_points() {
        let beam = NonlinearBeam::s1(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::new(-0.3, -0.3, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)],
        )
        .unwrap();
        let cone = beam.bounding_cone(&beam.extremal_directions(), 0.0);
        for i in 0..=10 {
            for j in 0..=10 - i {
                let w = Vec3::new(i as f32, j as f32, (10 - i - j) as f32) / 10.0;
                for t in [0.0, 0.5, 3.0, 50.0] {
                    assert!(cone.contains(beam.ray_at(w).at(t)), "{w} {t}");
                }
            }
        }
        assert!(!cone.contains(Vec3::new(0.3, 0.3, -5.0)));
    }

    #[test]
    fn parallel_beam_has_a_finite_apex() {
        let beam = NonlinearBeam::s1([Vec3::ZERO, Vec3::X, Vec3::Y], [Vec3::Z; 3]).unwrap();
        let cone = beam.bounding_cone(&beam.dirs, 0.0);
        assert!(cone.apex.is_finite() && cone.contains(Vec3::new(0.9, 0.05, 10.0)));
    }
}
