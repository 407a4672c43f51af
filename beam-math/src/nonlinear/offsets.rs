//! Maximum offsets `μ_b`, `μ_d` between the S^n and S1 parameterizations (000 eq. 4).

use super::beam::NonlinearBeam;
use super::parameterization::Interpolant;
use glam::DVec3;

impl<L: Interpolant> NonlinearBeam<L> {
    /// Upper bounds of `μ_b = max ‖O_P − Σωᵢ Pᵢ‖` and `μ_d = max ‖d_P − Σωᵢ dᵢ‖` over the base
    /// (000 eq. 4). The difference of the two patches is a Bézier triangle whose control points are
    /// `c_ijk − (i·X1 + j·X2 + k·X3)/n` (S1 raised to degree `n`); by the convex-hull property its
    /// largest control point bounds the maximum, so bounding triangles stay conservative. Both are
    /// zero for S1.
    #[must_use]
    pub fn max_offsets(&self) -> (f32, f32) {
        let p = &self.patch;
        let n = p.degree as f64;
        let base = self.base.map(|v| v.as_dvec3());
        let dirs = self.dirs.map(|v| v.as_dvec3());
        let lin =
            |x: &[DVec3; 3], ijk: [usize; 3]| (ijk[0] as f64 * x[0] + ijk[1] as f64 * x[1] + ijk[2] as f64 * x[2]) / n;
        let mut mu = (0.0f64, 0.0f64);
        for c in 0..p.count {
            mu.0 = mu.0.max((p.origin[c] - lin(&base, p.ijk[c])).length());
            mu.1 = mu.1.max((p.direction[c] - lin(&dirs, p.ijk[c])).length());
        }
        // Round up so that the f32 value is never below the f64 bound.
        let up = |x: f64| (x * (1.0 + 1e-6)) as f32;
        (up(mu.0), up(mu.1))
    }
}

#[cfg(test)]
mod tests {
    use super::super::parameterization::S3;
    use super::*;
    use glam::Vec3;

    #[test]
    fn s1_has_no_offset_and_s3_bounds_samples() {
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let dirs = [Vec3::new(-0.2, -0.2, 1.0), Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.0, 0.3, 1.0)];
        assert_eq!(NonlinearBeam::s1(base, dirs).unwrap().max_offsets(), (0.0, 0.0));
        let normals = [
            Vec3::new(-0.4, -0.4, 1.0).normalize(),
            Vec3::new(0.5, 0.0, 1.0).normalize(),
            Vec3::new(0.0, 0.5, 1.0).normalize(),
        ];
        let beam = NonlinearBeam::new(base, dirs, S3 { normals }).unwrap();
        let (mu_b, mu_d) = beam.max_offsets();
        assert!(mu_b > 0.0);
        let mut seen = (0.0f32, 0.0f32);
        for i in 0..=20 {
            for j in 0..=20 - i {
                let w = Vec3::new(i as f32, j as f32, (20 - i - j) as f32) / 20.0;
                let r = beam.ray_at(w);
                let lin_o = w.x * base[0] + w.y * base[1] + w.z * base[2];
                let lin_d = w.x * beam.dirs[0] + w.y * beam.dirs[1] + w.z * beam.dirs[2];
                seen.0 = seen.0.max((r.origin - lin_o).length());
                seen.1 = seen.1.max((r.direction - lin_d).length());
            }
        }
        assert!(seen.0 <= mu_b * 1.0001 && seen.1 <= mu_d * 1.0001 + 1e-7, "{seen:?} vs {mu_b} {mu_d}");
        // The bound is not absurdly loose.
        assert!(mu_b < 4.0 * seen.0, "{mu_b} vs {}", seen.0);
    }
}
