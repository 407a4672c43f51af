//! Real roots of `a x⁴ + b x³ + c x² + d x + e`.

use super::{cubic, poly, poly::Roots};

/// Distinct real roots of `a x⁴ + b x³ + c x² + d x + e`, ascending, by isolation between the
/// critical points (the roots of the derivative cubic) and bracketed Newton refinement. Multiple
/// roots are found at critical points and reported once. Degrades to [`cubic`] when `a = 0`.
#[must_use]
pub fn quartic(a: f64, b: f64, c: f64, d: f64, e: f64) -> Roots<4> {
    if a == 0.0 {
        let r = cubic(b, c, d, e);
        return Roots::from_slice(r.as_slice());
    }
    let crit = cubic(4.0 * a, 3.0 * b, 2.0 * c, d);
    poly::roots_from_critical(&[e, d, c, b, a], crit.as_slice(), &[])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        // (x−1)(x−2)(x−3)(x−4) = x⁴ − 10x³ + 35x² − 50x + 24.
        let r = quartic(1.0, -10.0, 35.0, -50.0, 24.0);
        assert_eq!(r.len(), 4);
        for (x, e) in r.as_slice().iter().zip([1.0, 2.0, 3.0, 4.0]) {
            assert!((x - e).abs() < 1e-10);
        }
        // Two double roots: (x² − 1)² = x⁴ − 2x² + 1.
        let r = quartic(1.0, 0.0, -2.0, 0.0, 1.0);
        assert_eq!(r.as_slice().len(), 2, "{r:?}");
        // No real root: x⁴ + 1.
        assert!(quartic(1.0, 0.0, 0.0, 0.0, 1.0).is_empty());
    }
}
