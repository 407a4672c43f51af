//! Real roots of `a x³ + b x² + c x + d`.

use super::{poly, poly::Roots, quadratic};
use crate::float::Float;

/// Distinct real roots of `a x³ + b x² + c x + d`, ascending, by isolation between the critical
/// points (roots of `3a x² + 2b x + c`) and bracketed Newton refinement started from the closed
/// form's roots (`closed_form`). Double and triple roots are found at the critical points and
/// reported once. Degrades to [`quadratic`] when `a = 0`.
#[must_use]
pub fn cubic(a: f64, b: f64, c: f64, d: f64) -> Roots<3> {
    if a == 0.0 {
        let q = quadratic(b, c, d);
        return Roots::from_slice(q.as_slice());
    }
    let crit = quadratic(3.0 * a, 2.0 * b, c);
    let (guesses, n) = closed_form(b / a, c / a, d / a);
    poly::roots_from_critical(&[d, c, b, a], crit.as_slice(), &guesses[..n])
}

/// Approximate real roots of `x³ + b x² + c x + d` by Cardano's formula (one real root) or
/// Viète's trigonometric one (three): starting points only, as rounding can spoil them, which
/// saves the refinement most of its steps from a bracket's middle.
fn closed_form(b: f64, c: f64, d: f64) -> ([f64; 3], usize) {
    // x = y − b/3 gives y³ + p y + q.
    let shift = b / 3.0;
    let p = c - b * shift;
    let q = (2.0 * shift * shift - c) * shift + d;
    let disc = 0.25 * q * q + p * p * p / 27.0;
    if !disc.is_finite() {
        return ([0.0; 3], 0);
    }
    if disc > 0.0 || p >= 0.0 {
        let s = disc.max(0.0).sqrt_();
        let y = (-0.5 * q + s).cbrt_() + (-0.5 * q - s).cbrt_();
        return ([y - shift, 0.0, 0.0], 1);
    }
    let r = 2.0 * (-p / 3.0).sqrt_();
    let phi = (1.5 * q / p * (-3.0 / p).sqrt_()).clamp(-1.0, 1.0).acos_() / 3.0;
    let third = 2.0 * core::f64::consts::PI / 3.0;
    ([0.0, 1.0, 2.0].map(|k| r * (phi - third * k).cos_() - shift), 3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        let r = cubic(1.0, -6.0, 11.0, -6.0);
        assert_eq!(r.len(), 3);
        for (x, e) in r.as_slice().iter().zip([1.0, 2.0, 3.0]) {
            assert!((x - e).abs() < 1e-12);
        }
        // Double root at 1 and simple at −2: (x − 1)²(x + 2) = x³ − 3x + 2.
        let r = cubic(1.0, 0.0, -3.0, 2.0);
        assert_eq!(r.len(), 2, "{r:?}");
        assert!((r.as_slice()[0] + 2.0).abs() < 1e-12 && (r.as_slice()[1] - 1.0).abs() < 1e-8);
        // Triple root: (x − 0.5)³.
        let r = cubic(1.0, -1.5, 0.75, -0.125);
        assert_eq!(r.len(), 1, "{r:?}");
        assert!((r.as_slice()[0] - 0.5).abs() < 1e-5);
        // One real root.
        assert_eq!(cubic(1.0, 0.0, 1.0, 1.0).len(), 1);
    }

    #[test]
    fn closed_form_starts_near_the_roots() {
        // (x − 1)(x − 2)(x − 3) = x³ − 6x² + 11x − 6: three real roots (Viète).
        let (g, n) = closed_form(-6.0, 11.0, -6.0);
        let mut g = g[..n].to_vec();
        g.sort_by(f64::total_cmp);
        assert_eq!(n, 3);
        for (x, e) in g.iter().zip([1.0, 2.0, 3.0]) {
            assert!((x - e).abs() < 1e-9, "{g:?}");
        }
        // (x − 2)(x² + 1) = x³ − 2x² + x − 2: one real root (Cardano).
        let (g, n) = closed_form(-2.0, 1.0, -2.0);
        assert!(n == 1 && (g[0] - 2.0).abs() < 1e-9, "{g:?}");
        // A tiny leading coefficient (nearly parallel S1 rays): a root near −b/a = −1e9 and the
        // quadratic's two; the refined roots solve the cubic whatever the guesses were.
        let (a, b, c, d) = (1e-9, 1.0, -3.0, 2.0);
        let r = cubic(a, b, c, d);
        assert_eq!(r.len(), 3, "{r:?}");
        for &x in r.as_slice() {
            let p = ((a * x + b) * x + c) * x + d;
            let scale = ((a * x.abs() + b) * x.abs() + c.abs()) * x.abs() + d;
            assert!(p.abs() <= 1e-12 * scale, "{x}: {p}");
        }
    }
}
