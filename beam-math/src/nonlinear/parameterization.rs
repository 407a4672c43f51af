//! The smooth S^n beam parameterization of 000 §4, eq. 1: ray origins and directions are triangular
//! Bézier patches over the base triangle whose coefficients come from one coefficient function
//! `L_ijk` applied to the base vertices and to the vertex directions. S1 is eq. 3, S3 is eq. 6.

use glam::{DVec3, Vec3};

/// Highest supported degree `n` (10 coefficients): 000's S1 and S3.
pub const MAX_DEGREE: usize = 3;
/// Coefficients of a degree-`MAX_DEGREE` triangular patch.
pub const MAX_COEFFICIENTS: usize = (MAX_DEGREE + 1) * (MAX_DEGREE + 2) / 2;

/// A coefficient function `L_ijk(X1, X2, X3)` of 000 eq. 1. Implementations must satisfy the
/// linearity of eq. 2, `L(P + s·d) = L(P) + s·L(d)`, on which the affine planes, threshold plane and
/// bounding triangles rely (000 App. B.1, B.3).
pub trait Interpolant: Copy {
    /// The degree `n`, at most [`MAX_DEGREE`].
    fn degree(&self) -> usize;
    /// `L_ijk(X1, X2, X3)` for `i + j + k = n`, including the multinomial factor `n!/(i!j!k!)`.
    fn coefficient(&self, ijk: [usize; 3], x: &[Vec3; 3]) -> Vec3;
}

/// The C⁰ parameterization of eq. 3: `O = Σ ωᵢPᵢ`, `d = Σ ωᵢdᵢ` (`n = 1`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct S1;

impl Interpolant for S1 {
    fn degree(&self) -> usize {
        1
    }
    fn coefficient(&self, ijk: [usize; 3], x: &[Vec3; 3]) -> Vec3 {
        match ijk {
            [1, 0, 0] => x[0],
            [0, 1, 0] => x[1],
            _ => x[2],
        }
    }
}

/// The cubic parameterization of eq. 6 (after Vlachos et al.'s PN triangles), C¹ at the S-mesh
/// vertices: `L_ijk = 3!/(i!j!k!)·c_ijk` with edge coefficients bent by the vertex normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct S3 {
    /// Unit normals `nᵢ` of the S mesh at the base vertices `Pᵢ`.
    pub normals: [Vec3; 3],
}

impl S3 {
    /// `c_ijk` of eq. 6.
    fn control(&self, ijk: [usize; 3], x: &[Vec3; 3]) -> Vec3 {
        let n = &self.normals;
        let w = |i: usize, j: usize| (x[j] - x[i]).dot(n[i]);
        let edge = |i: usize, j: usize| (2.0 * x[i] + x[j] - w(i, j) * n[i]) / 3.0;
        match ijk {
            [3, 0, 0] => x[0],
            [0, 3, 0] => x[1],
            [0, 0, 3] => x[2],
            [2, 1, 0] => edge(0, 1),
            [1, 2, 0] => edge(1, 0),
            [0, 2, 1] => edge(1, 2),
            [0, 1, 2] => edge(2, 1),
            [1, 0, 2] => edge(2, 0),
            [2, 0, 1] => edge(0, 2),
            _ => {
                let c = (edge(0, 1) + edge(1, 0) + edge(1, 2) + edge(2, 1) + edge(2, 0) + edge(0, 2)) / 6.0;
                let v = (x[0] + x[1] + x[2]) / 3.0;
                c + (c - v) / 2.0
            }
        }
    }
}

impl Interpolant for S3 {
    fn degree(&self) -> usize {
        3
    }
    fn coefficient(&self, ijk: [usize; 3], x: &[Vec3; 3]) -> Vec3 {
        multinomial(3, ijk) as f32 * self.control(ijk, x)
    }
}

/// `x^e` for every `e` up to [`MAX_DEGREE`], each by repeated multiplication (`core` has no
/// `powi`): `x^e = x^(e−1)·x`.
fn powers(x: f64) -> [f64; MAX_DEGREE + 1] {
    let mut p = [1.0; MAX_DEGREE + 1];
    for e in 1..=MAX_DEGREE {
        p[e] = p[e - 1] * x;
    }
    p
}

/// `n!/(i!j!k!)`.
#[must_use]
pub fn multinomial(n: usize, ijk: [usize; 3]) -> u32 {
    let f = |k: usize| (1..=k as u32).product::<u32>();
    f(n) / (f(ijk[0]) * f(ijk[1]) * f(ijk[2]))
}

/// The indices `(i, j, k)` with `i + j + k = n` in a fixed order.
pub fn indices(n: usize) -> impl Iterator<Item = [usize; 3]> {
    (0..=n).rev().flat_map(move |i| (0..=n - i).rev().map(move |j| [i, j, n - i - j]))
}

/// [`indices`]`(1)`, as a constant.
const IJK_S1: [[usize; 3]; 3] = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
/// [`indices`]`(3)`, as a constant.
const IJK_S3: [[usize; 3]; 10] =
    [[3, 0, 0], [2, 1, 0], [2, 0, 1], [1, 2, 0], [1, 1, 1], [1, 0, 2], [0, 3, 0], [0, 2, 1], [0, 1, 2], [0, 0, 3]];

/// The two Bézier patches of a beam (`O(ω)` and `d(ω)`) in Bernstein form and double precision:
/// control points `c_ijk = L_ijk / (n!/(i!j!k!))`, so both patches lie in the convex hull of their
/// control points (used by [`NonlinearBeam::max_offsets`](crate::nonlinear::NonlinearBeam::max_offsets) and the extremal directions).
#[derive(Clone, Copy, Debug)]
pub struct Patch {
    /// Degree `n`.
    pub degree: usize,
    /// Number of control points, `(n + 1)(n + 2)/2`.
    pub count: usize,
    /// `(i, j, k)` of each control point.
    pub ijk: [[usize; 3]; MAX_COEFFICIENTS],
    /// `n!/(i!j!k!)` of each control point.
    pub multinomial: [f64; MAX_COEFFICIENTS],
    /// Origin control points.
    pub origin: [DVec3; MAX_COEFFICIENTS],
    /// Direction control points.
    pub direction: [DVec3; MAX_COEFFICIENTS],
}

impl Patch {
    /// The patches of `L` applied to the base vertices and to the directions.
    #[must_use]
    pub fn new<L: Interpolant>(interp: &L, base: &[Vec3; 3], dirs: &[Vec3; 3]) -> Self {
        let degree = interp.degree().clamp(1, MAX_DEGREE);
        let mut p = Self {
            degree,
            count: 0,
            ijk: [[0; 3]; MAX_COEFFICIENTS],
            multinomial: [0.0; MAX_COEFFICIENTS],
            origin: [DVec3::ZERO; MAX_COEFFICIENTS],
            direction: [DVec3::ZERO; MAX_COEFFICIENTS],
        };
        for ijk in indices(degree) {
            let m = f64::from(multinomial(degree, ijk));
            p.ijk[p.count] = ijk;
            p.multinomial[p.count] = m;
            p.origin[p.count] = interp.coefficient(ijk, base).as_dvec3() / m;
            p.direction[p.count] = interp.coefficient(ijk, dirs).as_dvec3() / m;
            p.count += 1;
        }
        p
    }

    /// Bernstein weights `n!/(i!j!k!) ω1^i ω2^j ω3^k` of the first `min(N, count)` control points
    /// at `w` (the rest 0); `ijk` is `self.ijk` or a constant copy of its first `N`.
    #[inline(always)]
    fn weights<const N: usize>(&self, w: DVec3, ijk: &[[usize; 3]; N]) -> [f64; N] {
        debug_assert_eq!(ijk[..], self.ijk[..N]);
        let [x, y, z] = [w.x, w.y, w.z].map(powers);
        let mut out = [0.0; N];
        for ((o, ijk), m) in out.iter_mut().zip(&ijk[..self.count.min(N)]).zip(&self.multinomial) {
            *o = m * x[ijk[0]] * y[ijk[1]] * z[ijk[2]];
        }
        out
    }

    /// `(O(ω), d(ω))` of eq. 1 at barycentric coordinates `w`: `Σ B_ijk(ω) c_ijk` over the
    /// Bernstein weights `B_ijk = n!/(i!j!k!) ω1^i ω2^j ω3^k`, in the order of [`indices`]. S1 and
    /// S3 patches take a loop unrolled for their count (the same operations in the same order, so
    /// the same bits).
    #[must_use]
    pub fn eval(&self, w: DVec3) -> (DVec3, DVec3) {
        match self.count {
            3 => self.eval_n::<3>(w, &IJK_S1),
            10 => self.eval_n::<10>(w, &IJK_S3),
            _ => self.eval_n::<MAX_COEFFICIENTS>(w, &self.ijk),
        }
    }

    /// [`Patch::eval`] over the first `min(N, count)` control points.
    #[inline(always)]
    fn eval_n<const N: usize>(&self, w: DVec3, ijk: &[[usize; 3]; N]) -> (DVec3, DVec3) {
        let b = self.weights::<N>(w, ijk);
        let mut o = DVec3::ZERO;
        let mut d = DVec3::ZERO;
        for c in 0..N.min(self.count) {
            o += b[c] * self.origin[c];
            d += b[c] * self.direction[c];
        }
        (o, d)
    }

    /// Partial derivatives of `O` and `d` with respect to `ω1` and `ω2` (with `ω3 = 1 − ω1 − ω2`).
    /// S1 and S3 patches take a loop unrolled for their count, as [`Patch::eval`] does (the same
    /// operations in the same order, so the same bits).
    #[must_use]
    pub fn derivatives(&self, w: DVec3) -> [(DVec3, DVec3); 2] {
        match self.count {
            3 => self.derivatives_n::<3>(w, &IJK_S1),
            10 => self.derivatives_n::<10>(w, &IJK_S3),
            _ => self.derivatives_n::<MAX_COEFFICIENTS>(w, &self.ijk),
        }
    }

    /// [`Patch::derivatives`] over the first `min(N, count)` control points; `ijk` is `self.ijk`
    /// or a constant copy of its first `N`.
    #[inline(always)]
    fn derivatives_n<const N: usize>(&self, w: DVec3, ijk: &[[usize; 3]; N]) -> [(DVec3, DVec3); 2] {
        debug_assert_eq!(ijk[..], self.ijk[..N]);
        let [x, y, z] = [w.x, w.y, w.z].map(powers);
        // `e·x^(e−1)`, 0 for `e = 0`.
        let d = |p: &[f64; MAX_DEGREE + 1], e: usize| if e == 0 { 0.0 } else { e as f64 * p[e - 1] };
        let mut out = [(DVec3::ZERO, DVec3::ZERO); 2];
        for c in 0..N.min(self.count) {
            let [i, j, k] = ijk[c];
            let m = self.multinomial[c];
            let d1 = m * (d(&x, i) * y[j] * z[k] - x[i] * y[j] * d(&z, k));
            let d2 = m * (x[i] * d(&y, j) * z[k] - x[i] * y[j] * d(&z, k));
            out[0].0 += d1 * self.origin[c];
            out[0].1 += d1 * self.direction[c];
            out[1].0 += d2 * self.origin[c];
            out[1].1 += d2 * self.direction[c];
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ([Vec3; 3], [Vec3; 3]) {
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let dirs = [Vec3::new(-0.2, -0.1, 1.0), Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.0, 0.4, 1.0)];
        (base, dirs)
    }

    #[test]
    fn s1_interpolates_linearly() {
        let (base, dirs) = sample();
        let p = Patch::new(&S1, &base, &dirs);
        let w = DVec3::new(0.2, 0.3, 0.5);
        let (o, d) = p.eval(w);
        let expect_o = 0.2 * base[0] + 0.3 * base[1] + 0.5 * base[2];
        let expect_d = 0.2 * dirs[0] + 0.3 * dirs[1] + 0.5 * dirs[2];
        assert!((o - expect_o.as_dvec3()).length() < 1e-7 && (d - expect_d.as_dvec3()).length() < 1e-7);
    }

    #[test]
    fn s3_interpolates_vertices_and_is_linear_eq2() {
        let (base, dirs) = sample();
        let s3 = S3 {
            normals: [
                Vec3::new(-0.3, -0.3, 1.0).normalize(),
                Vec3::new(0.4, 0.0, 1.0).normalize(),
                Vec3::new(0.0, 0.5, 1.0).normalize(),
            ],
        };
        let p = Patch::new(&s3, &base, &dirs);
        for (i, w) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            let (o, d) = p.eval(w);
            assert!((o - base[i].as_dvec3()).length() < 1e-6 && (d - dirs[i].as_dvec3()).length() < 1e-6);
        }
        // eq. 2: L(P + s d) = L(P) + s L(d) for every coefficient.
        let s = 0.7;
        let moved = [base[0] + s * dirs[0], base[1] + s * dirs[1], base[2] + s * dirs[2]];
        for ijk in indices(3) {
            let lhs = s3.coefficient(ijk, &moved);
            let rhs = s3.coefficient(ijk, &base) + s * s3.coefficient(ijk, &dirs);
            assert!((lhs - rhs).length() < 1e-5, "{ijk:?}");
        }
        // Weights sum to one (partition of unity).
        let b = p.weights::<MAX_COEFFICIENTS>(DVec3::new(0.1, 0.6, 0.3), &p.ijk);
        assert!((b[..p.count].iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn constant_indices_are_the_indices() {
        assert!(indices(1).eq(IJK_S1));
        assert!(indices(3).eq(IJK_S3));
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let (base, dirs) = sample();
        let s3 =
            S3 { normals: [Vec3::new(-0.3, -0.3, 1.0).normalize(), Vec3::Z, Vec3::new(0.0, 0.5, 1.0).normalize()] };
        let p = Patch::new(&s3, &base, &dirs);
        let w = DVec3::new(0.2, 0.5, 0.3);
        let h = 1e-6;
        let der = p.derivatives(w);
        let (o1, d1) = p.eval(w + DVec3::new(h, 0.0, -h));
        let (o0, d0) = p.eval(w - DVec3::new(h, 0.0, -h));
        assert!(((o1 - o0) / (2.0 * h) - der[0].0).length() < 1e-6);
        assert!(((d1 - d0) / (2.0 * h) - der[0].1).length() < 1e-6);
    }

    /// The loops unrolled for S1 and S3 give the generic loop's bits.
    #[test]
    fn unrolled_patches_equal_the_generic_loop() {
        let (base, dirs) = sample();
        let s3 =
            S3 { normals: [Vec3::new(-0.3, -0.3, 1.0).normalize(), Vec3::Z, Vec3::new(0.1, 0.5, 1.0).normalize()] };
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        for p in [Patch::new(&S1, &base, &dirs), Patch::new(&s3, &base, &dirs)] {
            for k in 0..200 {
                let (a, b) = (f64::from(k % 17) / 8.0 - 0.5, f64::from(k / 17) / 6.0 - 0.4);
                let w = DVec3::new(a, b, 1.0 - a - b);
                let (o, d) = p.eval(w);
                let (go, gd) = p.eval_n::<MAX_COEFFICIENTS>(w, &p.ijk);
                assert_eq!((bits(o), bits(d)), (bits(go), bits(gd)), "eval at {w}");
                let got = p.derivatives(w).map(|(o, d)| (bits(o), bits(d)));
                let want = p.derivatives_n::<MAX_COEFFICIENTS>(w, &p.ijk).map(|(o, d)| (bits(o), bits(d)));
                assert_eq!(got, want, "derivatives at {w}");
            }
        }
    }

    #[test]
    fn multinomials() {
        assert_eq!(multinomial(3, [1, 1, 1]), 6);
        assert_eq!(multinomial(3, [2, 1, 0]), 3);
        assert_eq!(indices(3).count(), 10);
    }
}
