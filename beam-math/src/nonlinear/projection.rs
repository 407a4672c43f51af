//! Projection (000 §5, Fig. 3b): the points `P` of the base with `Q = O_P + t·d_P`. For S1 this is
//! the cubic `[(H2 − H1) × (H3 − H1)]·(Q − H1) = 0` in `t` (Q lies on the affine plane `Πa(t)`), then
//! the barycentric coordinates of `Q` in `Δa(t)` (the barycentric invariance of §5). For S^n the
//! base is subdivided, each piece solved as a local S1 beam and the candidates polished by Newton's
//! method on the full eq. 1.

use super::beam::NonlinearBeam;
use super::parameterization::Interpolant;
use crate::roots::cubic;
use glam::{DMat3, DVec3, Vec3};

/// One projection: barycentric coordinates on the base and the ray parameter, `Q = O_P + t·d_P`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Barycentric coordinates `ω` of `P` on the base triangle.
    pub bary: Vec3,
    /// Ray parameter `t` (with the beam's unit boundary directions).
    pub t: f32,
}

/// Up to [`Projections::CAPACITY`] projections, sorted by `t`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Projections {
    items: [Option<Projection>; 9],
    len: usize,
}

impl Projections {
    /// Maximum number of projections kept.
    pub const CAPACITY: usize = 9;

    /// The projections, ascending in `t`.
    pub fn iter(&self) -> impl Iterator<Item = Projection> + '_ {
        self.items[..self.len].iter().flatten().copied()
    }

    /// Number of projections.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there is none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn push_unique(&mut self, p: Projection, tol: f32) {
        let dup = self
            .iter()
            .any(|q| (q.bary - p.bary).abs().max_element() <= tol && (q.t - p.t).abs() <= tol * (1.0 + p.t.abs()));
        if dup || self.len == Self::CAPACITY {
            return;
        }
        let mut i = self.len;
        while i > 0 && self.items[i - 1].is_some_and(|q| q.t > p.t) {
            self.items[i] = self.items[i - 1];
            i -= 1;
        }
        self.items[i] = Some(p);
        self.len += 1;
    }
}

/// Newton steps of a projection at full precision.
pub const NEWTON_STEPS: u32 = 60;

/// How far Newton's method polishes an S^n projection: at most `steps` steps, done where the
/// residual `|O(ω) + t·d(ω) − Q|` is at most `tolerance · s · (1 + |t|)` (`s` the base's size).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polish {
    /// Most Newton steps.
    pub steps: u32,
    /// Residual, relative to the base's size, below which a step ends the method.
    pub tolerance: f64,
}

impl Polish {
    /// Full precision: [`NEWTON_STEPS`] steps, residual 10⁻¹² (the tree's directions, 000 §7.2).
    pub const FULL: Self = Self { steps: NEWTON_STEPS, tolerance: 1e-12 };

    /// Residual below which an answer is accepted after the last step.
    const ACCEPT: f64 = 1e-7;
}

/// Tolerance on barycentric coordinates for "inside the base triangle".
pub const BARY_TOLERANCE: f32 = 1e-5;

/// Real roots `t` of `[(H2 − H1) × (H3 − H1)]·(Q − H1)` for `Hᵢ = Pᵢ + t·dᵢ` with the barycentric
/// coordinates of `Q` in `Δa(t)`: every S1 projection, inside the base triangle or not.
pub(crate) fn s1_solutions(p: [DVec3; 3], d: [DVec3; 3], q: DVec3) -> ([(DVec3, f64); 3], usize) {
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let f1 = d[1] - d[0];
    let f2 = d[2] - d[0];
    let r = q - p[0];
    let dd = -d[0];
    let n0 = e1.cross(e2);
    let n1 = e1.cross(f2) + f1.cross(e2);
    let n2 = f1.cross(f2);
    let roots = cubic(n2.dot(dd), n2.dot(r) + n1.dot(dd), n1.dot(r) + n0.dot(dd), n0.dot(r));
    let mut out = [(DVec3::ZERO, 0.0); 3];
    let mut len = 0;
    for &t in roots.as_slice() {
        let h = [p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]];
        let n = (h[1] - h[0]).cross(h[2] - h[0]);
        let nn = n.length_squared();
        if !(nn > 0.0) {
            continue;
        }
        let w0 = (h[1] - q).cross(h[2] - q).dot(n) / nn;
        let w1 = (h[2] - q).cross(h[0] - q).dot(n) / nn;
        out[len] = (DVec3::new(w0, w1, 1.0 - w0 - w1), t);
        len += 1;
    }
    (out, len)
}

impl<L: Interpolant> NonlinearBeam<L> {
    /// Every projection of `q` whose barycentric coordinates lie in the base triangle (within
    /// [`BARY_TOLERANCE`]), any sign of `t` (000 §5, *Projection*). At most 3 for S1.
    #[must_use]
    pub fn project(&self, q: Vec3) -> Projections {
        let mut out = Projections::default();
        if self.degree() == 1 {
            let (sol, n) = s1_solutions(self.base.map(|v| v.as_dvec3()), self.dirs.map(|v| v.as_dvec3()), q.as_dvec3());
            for &(w, t) in &sol[..n] {
                if w.min_element() >= -f64::from(BARY_TOLERANCE) {
                    out.push_unique(Projection { bary: w.as_vec3(), t: t as f32 }, BARY_TOLERANCE);
                }
            }
            return out;
        }
        self.project_sn(q, &mut out);
        out
    }

    /// The projection of `q` with `t > 0` nearest the base triangle, extrapolating the
    /// parameterization beyond the base when `q` lies outside the beam: the direction a beam carries
    /// to the vertices of a surface it only partly covers (000 §7.2). S1 by the cubic; S^n by the
    /// S1 beam of its corner rays, polished by Newton's method on the full eq. 1.
    #[must_use]
    pub fn project_nearest(&self, q: Vec3) -> Option<Projection> {
        self.project_nearest_in(q, Polish::FULL)
    }

    /// [`Self::project_nearest`] polished as `polish` says; where Newton's method does not
    /// converge, the last iterate if its residual is within 10⁻⁷ of the base's size, else the
    /// corner rays' S1 solution, as after all [`NEWTON_STEPS`]. For lookups that need `ω` to a
    /// fraction of a texel: a point that no ray of the S^n beam reaches (beyond a fold of its
    /// extrapolated rays, common for a point outside the beam) spends every step it is given
    /// before it fails.
    #[must_use]
    pub fn project_nearest_in(&self, q: Vec3, polish: Polish) -> Option<Projection> {
        let (sol, n) = s1_solutions(self.base.map(|v| v.as_dvec3()), self.dirs.map(|v| v.as_dvec3()), q.as_dvec3());
        let outside = |w: DVec3| (-w.min_element()).max(0.0);
        let &(mut w, mut t) =
            sol[..n].iter().filter(|(_, t)| *t > 0.0).min_by(|a, b| outside(a.0).total_cmp(&outside(b.0)))?;
        if self.degree() > 1 {
            (w, t) = self.newton(q.as_dvec3(), w, t, polish).filter(|(_, t)| *t > 0.0).unwrap_or((w, t));
        }
        Some(Projection { bary: w.as_vec3(), t: t as f32 })
    }

    /// [`Self::project_nearest_in`] started from `guess` instead of the corner rays' S1 solution,
    /// for a point whose projection lies near a known one (a lookup's first projection starts
    /// from the point's own place on the face, its second from its first): Newton's method needs
    /// fewer steps and the cubic is not solved. Where it does not converge from `guess` or
    /// reaches `t ≤ 0`, the corner rays' S1 solution, unpolished: such a point is rarely reached
    /// from there either, and it would spend every step again. S1 beams solve the cubic as always.
    #[must_use]
    pub fn project_nearest_from(&self, q: Vec3, guess: Projection, polish: Polish) -> Option<Projection> {
        if self.degree() > 1 && guess.bary.is_finite() && guess.t.is_finite() {
            let (w, t) = (guess.bary.as_dvec3(), f64::from(guess.t));
            if let Some((w, t)) = self.newton(q.as_dvec3(), w, t, polish).filter(|(_, t)| *t > 0.0) {
                return Some(Projection { bary: w.as_vec3(), t: t as f32 });
            }
            return self.project_nearest_in(q, Polish { steps: 0, ..polish });
        }
        self.project_nearest_in(q, polish)
    }

    /// The base's size for Newton's tolerances: its largest distance from the first vertex.
    fn scale(&self) -> f64 {
        self.base.iter().fold(0.0f64, |m, p| m.max(f64::from(p.distance(self.base[0])))).max(1e-30)
    }

    /// S^n projection: subdivide the base into `K²` triangles, solve each as an S1 beam through its
    /// corner rays, and polish every candidate with Newton's method on `O(ω) + t·d(ω) − Q = 0`.
    fn project_sn(&self, q: Vec3, out: &mut Projections) {
        const K: usize = 10;
        let q = q.as_dvec3();
        let corner =
            |i: usize, j: usize| DVec3::new(i as f64 / K as f64, j as f64 / K as f64, (K - i - j) as f64 / K as f64);
        for i in 0..K {
            for j in 0..K - i {
                let mut tris = [[corner(i, j), corner(i + 1, j), corner(i, j + 1)], [DVec3::ZERO; 3]];
                let count = if i + j + 1 < K {
                    tris[1] = [corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)];
                    2
                } else {
                    1
                };
                for w in &tris[..count] {
                    let rays = w.map(|w| self.patch.eval(w));
                    let (sol, n) = s1_solutions(rays.map(|r| r.0), rays.map(|r| r.1), q);
                    for &(local, t) in &sol[..n] {
                        // A local S1 piece is only a first guess: far along strongly curved S^n rays
                        // its solution can land well outside the piece, so keep anything near it.
                        if local.min_element() < -2.0 {
                            continue;
                        }
                        let guess = w[0] * local.x + w[1] * local.y + w[2] * local.z;
                        if guess.min_element() < -0.5 {
                            continue;
                        }
                        if let Some((w, t)) = self.newton(q, guess, t, Polish::FULL) {
                            if w.min_element() >= -f64::from(BARY_TOLERANCE) {
                                out.push_unique(Projection { bary: w.as_vec3(), t: t as f32 }, 1e-4);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Damped Newton's method on `F(ω1, ω2, t) = O(ω) + t·d(ω) − Q` from an initial guess, as far as
    /// `polish` says: a step is halved until the residual decreases, which keeps it converging
    /// near folds of the beam (caustics) where the Jacobian is nearly singular.
    fn newton(&self, q: DVec3, mut w: DVec3, mut t: f64, polish: Polish) -> Option<(DVec3, f64)> {
        let scale = self.scale();
        // The residual at (w, t) and the ray direction d(w) it was computed with.
        let residual = |w: DVec3, t: f64| {
            let (o, d) = self.patch.eval(w);
            (o + t * d - q, d)
        };
        let (mut f, mut d) = residual(w, t);
        for _ in 0..polish.steps {
            if f.length() <= polish.tolerance * scale * (1.0 + t.abs()) {
                return Some((w, t));
            }
            let [(o1, d1), (o2, d2)] = self.patch.derivatives(w);
            let jac = DMat3::from_cols(o1 + t * d1, o2 + t * d2, d);
            if jac.determinant().abs() < 1e-300 {
                return None;
            }
            let step = jac.inverse() * f;
            let mut lambda = 1.0;
            loop {
                let w2 = DVec3::new(
                    w.x - lambda * step.x,
                    w.y - lambda * step.y,
                    1.0 - (w.x - lambda * step.x) - (w.y - lambda * step.y),
                );
                let t2 = t - lambda * step.z;
                let (f2, dir2) = residual(w2, t2);
                if f2.length() < f.length() || lambda < 1e-3 {
                    (w, t, f, d) = (w2, t2, f2, dir2);
                    break;
                }
                lambda *= 0.5;
            }
            if !w.is_finite() || !t.is_finite() || w.abs().max_element() > 10.0 {
                return None;
            }
        }
        (f.length() <= Polish::ACCEPT.max(polish.tolerance) * scale * (1.0 + t.abs())).then_some((w, t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_beam_projects_straight_down() {
        let beam = NonlinearBeam::s1([Vec3::ZERO, Vec3::X, Vec3::Y], [Vec3::Z; 3]).unwrap();
        let p = beam.project(Vec3::new(0.25, 0.25, 3.0));
        assert_eq!(p.len(), 1);
        let p = p.iter().next().unwrap();
        assert!((p.bary - Vec3::new(0.5, 0.25, 0.25)).length() < 1e-5 && (p.t - 3.0).abs() < 1e-5);
        assert!(beam.project(Vec3::new(2.0, 2.0, 1.0)).is_empty());
    }

    #[test]
    fn nearest_projection_extrapolates_outside_the_base() {
        let dirs = [Vec3::new(-0.3, -0.3, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)];
        let s1 = NonlinearBeam::s1([Vec3::ZERO, Vec3::X, Vec3::Y], dirs).unwrap();
        let s3 = NonlinearBeam::new(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            dirs,
            crate::nonlinear::S3 { normals: [Vec3::new(-0.1, -0.1, 1.0).normalize(), Vec3::Z, Vec3::Z] },
        )
        .unwrap();
        for w in [Vec3::new(0.2, 0.5, 0.3), Vec3::new(-0.4, 0.9, 0.5), Vec3::new(1.3, -0.1, -0.2)] {
            let q = s1.ray_at(w).at(2.0);
            let p = s1.project_nearest(q).unwrap();
            assert!((p.bary - w).length() < 1e-4, "{p:?} {w}");
            let q = s3.ray_at(w).at(2.0);
            let p = s3.project_nearest(q).unwrap();
            assert!((s3.ray_at(p.bary).at(p.t) - q).length() < 1e-4, "{p:?} {w}");
        }
    }

    #[test]
    fn bounded_projection_equals_full_where_it_converges() {
        let dirs = [Vec3::new(-0.3, -0.3, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)];
        let normals = [Vec3::new(-0.1, -0.1, 1.0).normalize(), Vec3::Z, Vec3::Z];
        let s3 = NonlinearBeam::new([Vec3::ZERO, Vec3::X, Vec3::Y], dirs, crate::nonlinear::S3 { normals }).unwrap();
        for w in [Vec3::new(0.2, 0.5, 0.3), Vec3::new(0.6, 0.1, 0.3), Vec3::new(1.2, -0.1, -0.1)] {
            let q = s3.ray_at(w).at(2.0);
            assert_eq!(s3.project_nearest_in(q, Polish { steps: 10, ..Polish::FULL }), s3.project_nearest(q));
            // No step: the S1 solution of the corner rays, off the S3 ray through `q`.
            let s1 = s3.project_nearest_in(q, Polish { steps: 0, ..Polish::FULL }).unwrap();
            assert!((s3.ray_at(s1.bary).at(s1.t) - q).length() > 1e-4, "{s1:?} {w}");
        }
    }

    #[test]
    fn projection_from_a_guess_finds_the_full_answer() {
        let dirs = [Vec3::new(-0.3, -0.3, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)];
        let normals = [Vec3::new(-0.1, -0.1, 1.0).normalize(), Vec3::Z, Vec3::Z];
        let s3 = NonlinearBeam::new([Vec3::ZERO, Vec3::X, Vec3::Y], dirs, crate::nonlinear::S3 { normals }).unwrap();
        let lookup = Polish { steps: 5, tolerance: 1e-6 };
        for w in [Vec3::new(0.2, 0.5, 0.3), Vec3::new(0.6, 0.1, 0.3), Vec3::new(1.2, -0.1, -0.1)] {
            let q = s3.ray_at(w).at(2.0);
            let full = s3.project_nearest(q).unwrap();
            // From a guess a few hundredths off in ω and 10% off in t.
            let guess = Projection { bary: w + Vec3::new(0.03, -0.02, -0.01), t: 2.2 };
            let p = s3.project_nearest_from(q, guess, lookup).unwrap();
            assert!((p.bary - full.bary).abs().max_element() < 1e-5 && (p.t - full.t).abs() < 1e-5, "{p:?} {full:?}");
        }
        // Where Newton's method does not converge from the guess (here in one step from far
        // off), the corner rays' S1 solution, unpolished.
        let q = s3.ray_at(Vec3::new(0.2, 0.5, 0.3)).at(2.0);
        let far_off = Projection { bary: Vec3::new(3.0, -1.0, -1.0), t: 9.0 };
        let unpolished = s3.project_nearest_in(q, Polish { steps: 0, ..Polish::FULL });
        assert!(unpolished.is_some() && unpolished != s3.project_nearest(q));
        assert_eq!(s3.project_nearest_from(q, far_off, Polish { steps: 1, ..lookup }), unpolished);
    }

    #[test]
    fn diverging_beam_round_trip() {
        let beam = NonlinearBeam::s1(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::new(-0.3, -0.3, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)],
        )
        .unwrap();
        let w = Vec3::new(0.2, 0.5, 0.3);
        let q = beam.ray_at(w).at(2.5);
        let p = beam.project(q);
        assert!(p.iter().any(|p| (p.bary - w).length() < 1e-4 && (p.t - 2.5).abs() < 1e-3), "{p:?}");
    }
}
