//! Real roots of `a x³ + b x² + c x + d`.

use super::{poly, poly::Roots, quadratic};

/// Distinct real roots of `a x³ + b x² + c x + d`, ascending, by isolation between the critical
/// points (roots of `3a x² + 2b x + c`) and bracketed Newton refinement. Double and triple roots
/// are found at the critical points and reported once. Degrades to [`quadratic`] when `a = 0`.
#[must_use]
pub fn cubic(a: f64, b: f64, c: f64, d: f64) -> Roots<3> {
    if a == 0.0 {
        let q = quadratic(b, c, d);
        return Roots::from_slice(q.as_slice());
    }
    let crit = quadratic(3.0 * a, 2.0 * b, c);
    poly::roots_from_critical(&[d, c, b, a], crit.as_slice())
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
}
