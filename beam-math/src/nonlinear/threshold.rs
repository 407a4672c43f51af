//! The threshold plane `Π_T = Πa(t_res)` (000 §5, §6.2, App. B.2): above it every point has at most
//! one projection in the base triangle.

use super::beam::NonlinearBeam;
use super::parameterization::Interpolant;
use crate::collide::triangle_triangle_distance;
use crate::roots::quadratic;
use crate::shapes::{Plane, Triangle};
use glam::Vec3;

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
    /// True unless every point of `tri` is strictly above the plane (000 Alg. 3's "Δ above Π_T"):
    /// some point of `tri` lies on or below it.
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
        self.threshold_plane_with(self.max_offsets())
    }

    /// [`Self::threshold_plane`] with the beam's `(μ_b, μ_d)` ([`Self::max_offsets`]) at hand.
    /// The triangles' distance is no more than that of any corner of one from its own corner of
    /// the other, so a step whose nearest pair of corners lies within the margin (a thousandth
    /// below it, for rounding) is doubled without computing the distance; and no less than their
    /// gap along either one's normal (a separating axis), so a step whose gap clears the margin (by a
    /// thousandth, for rounding) is taken without computing it either: the same `t_res`. The
    /// corners of a step move apart by `step·‖dᵢ‖`, so the steps whose nearest pair would lie
    /// within a quarter of the margin are not even tried (about six of ten on the wavy lake's S3
    /// beams).
    #[must_use]
    pub fn threshold_plane_with(&self, (mu_b, mu_d): (f32, f32)) -> ThresholdPlane {
        let mut t_max = 0.0f64;
        for [a, b, c] in self.threshold_quadratics() {
            for &t in quadratic(a, b, c).as_slice() {
                t_max = t_max.max(t);
            }
        }
        let t_max = t_max as f32;
        let size = self.base.iter().fold(0.0f32, |m, p| m.max(p.distance(self.base[0])));
        let margin = (mu_b + t_max * mu_d).max(1e-4 * size);
        let low = self.affine_triangle(t_max);
        let low_normal = unit_normal(&low);
        let mut step = 1e-3 * size.max(t_max * 1e-3);
        // Each corner moves by `step·‖dᵢ‖` (rounding aside), so a step whose nearest pair of
        // corners would lie within a quarter of the margin fails below: such steps are skipped.
        let reach = self.dirs.iter().fold(f32::INFINITY, |m, d| m.min(d.length()));
        let mut tries = 64;
        while tries > 1 && 4.0 * step * reach < 0.999 * margin {
            step *= 2.0;
            tries -= 1;
        }
        let mut t_res = f32::INFINITY;
        for _ in 0..tries {
            let t = t_max + step;
            let high = self.affine_triangle(t);
            let corners = (0..3).fold(f32::INFINITY, |m, i| m.min(high.v[i].distance(low.v[i])));
            if corners >= 0.999 * margin
                && (separation(&high, (&low, low_normal)) > 1.001 * margin
                    || triangle_triangle_distance(&high, &low) > margin)
            {
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

/// A lower bound of the distance between `a` and `b`: the larger gap between their projections
/// on `a`'s unit normal and on `b`'s, `b_normal` ([`unit_normal`], taken once for a `b` tested
/// against many `a`s): separating axes (any unit axis gives a lower bound, as each triangle is the
/// convex hull of its corners). Not a number where both are degenerate.
fn separation(a: &Triangle, (b, b_normal): (&Triangle, Vec3)) -> f32 {
    let gap = |n: Vec3| {
        let (pa, pb) = (a.v.map(|v| n.dot(v)), b.v.map(|v| n.dot(v)));
        let (lo_a, hi_a) = (pa[0].min(pa[1]).min(pa[2]), pa[0].max(pa[1]).max(pa[2]));
        let (lo_b, hi_b) = (pb[0].min(pb[1]).min(pb[2]), pb[0].max(pb[1]).max(pb[2]));
        (lo_a - hi_b).max(lo_b - hi_a)
    };
    gap(unit_normal(a)).max(gap(b_normal))
}

/// The unit normal of `t`; not a number where rounding left it short of unit length (a triangle
/// next to degenerate is no axis).
fn unit_normal(t: &Triangle) -> Vec3 {
    let n = t.scaled_normal().normalize_or_zero();
    if (n.length_squared() - 1.0).abs() < 1e-4 { n } else { Vec3::NAN }
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

    /// Skipping the steps whose nearest corners lie within the margin (and not trying those whose
    /// corners could not reach it), and taking those whose
    /// separation clears it, finds the same `t_res`, bit for bit, as computing every step's
    /// distance, on S1 and S3 beams that diverge, converge past their base or fan out (a fixed
    /// pseudo-random sequence).
    #[test]
    fn shortcuts_keep_t_res() {
        use super::super::parameterization::S3;
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        };
        let mut checked = 0;
        for _ in 0..2000 {
            let mut v = || Vec3::new(next(), next(), next());
            let base = [v(), v(), v()];
            let spread = 0.6 * v().x.abs();
            let dirs = [0, 1, 2].map(|_| (Vec3::Z + spread * v()).normalize());
            let normals = [0, 1, 2].map(|_| (Vec3::Z + 0.3 * v()).normalize());
            let s1 = NonlinearBeam::s1(base, dirs).map(|b| (b.threshold_plane(), full_search(&b)));
            let s3 = NonlinearBeam::new(base, dirs, S3 { normals }).map(|b| (b.threshold_plane(), full_search(&b)));
            for (fast, full) in [s1, s3].into_iter().flatten() {
                assert_eq!(fast.t_res.to_bits(), full.to_bits(), "{fast:?} vs {full}");
                checked += 1;
            }
        }
        assert!(checked > 2000, "{checked}");
    }

    /// The separation never exceeds the distance (pairs of random triangles, some parallel and
    /// some degenerate), and equals it for a triangle lifted straight off its copy.
    #[test]
    fn separation_bounds_the_distance() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        };
        let mut separated = 0;
        for k in 0..3000 {
            let mut v = || Vec3::new(next(), next(), next());
            let a = Triangle { v: [v(), v(), v()] };
            let b = match k % 3 {
                0 => Triangle { v: [v(), v(), v()] },
                1 => Triangle { v: a.v.map(|p| p + 0.5 * v()) },
                _ => Triangle { v: [a.v[0], a.v[0] + v(), a.v[0]] },
            };
            let (lower, dist) = (separation(&a, (&b, unit_normal(&b))), triangle_triangle_distance(&a, &b));
            assert!(!(lower > dist * (1.0 + 1e-4) + 1e-6), "{lower} > {dist} for {a:?}, {b:?}");
            separated += usize::from(lower > 0.0);
        }
        assert!(separated > 300, "{separated}");
        let a = Triangle { v: [Vec3::ZERO, Vec3::X, Vec3::Y] };
        let up = Triangle { v: a.v.map(|p| p + 0.25 * Vec3::Z) };
        assert!((separation(&a, (&up, unit_normal(&up))) - 0.25).abs() < 1e-6);
    }

    /// `t_res` by the distance at every doubling step (the search without the corner shortcut).
    fn full_search<L: Interpolant>(b: &NonlinearBeam<L>) -> f32 {
        let t_max = b.threshold_plane().t_max;
        let (mu_b, mu_d) = b.max_offsets();
        let size = b.base.iter().fold(0.0f32, |m, p| m.max(p.distance(b.base[0])));
        let margin = (mu_b + t_max * mu_d).max(1e-4 * size);
        let low = b.affine_triangle(t_max);
        let mut step = 1e-3 * size.max(t_max * 1e-3);
        for _ in 0..64 {
            if triangle_triangle_distance(&b.affine_triangle(t_max + step), &low) > margin {
                return t_max + step;
            }
            step *= 2.0;
        }
        f32::INFINITY
    }
}
