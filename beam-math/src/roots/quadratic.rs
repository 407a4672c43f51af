//! Real roots of `a x² + b x + c`.

use super::poly::Roots;
use crate::float::Float;

/// Distinct real roots of `a x² + b x + c`, ascending. Uses the cancellation-free pair
/// `q = −½(b + sign(b)√Δ)`, `x₁ = q/a`, `x₂ = c/q`; a discriminant within rounding of zero gives the
/// double root `−b/2a` once. Degrades to the linear case when `a = 0`.
#[must_use]
pub fn quadratic(a: f64, b: f64, c: f64) -> Roots<2> {
    if a == 0.0 {
        if b == 0.0 {
            return Roots::default();
        }
        return Roots::from_slice(&[-c / b]);
    }
    let disc = b * b - 4.0 * a * c;
    let err = 8.0 * f64::EPSILON * (b * b + (4.0 * a * c).abs());
    if disc.abs() <= err {
        return Roots::from_slice(&[-b / (2.0 * a)]);
    }
    if disc < 0.0 {
        return Roots::default();
    }
    let s = disc.sqrt_();
    let q = -0.5 * (b + if b >= 0.0 { s } else { -s });
    if q == 0.0 {
        return Roots::from_slice(&[0.0]);
    }
    Roots::from_slice(&[q / a, c / q])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        assert_eq!(quadratic(1.0, -3.0, 2.0).as_slice(), &[1.0, 2.0]);
        assert_eq!(quadratic(1.0, -2.0, 1.0).as_slice(), &[1.0]);
        assert!(quadratic(1.0, 0.0, 1.0).is_empty());
        assert_eq!(quadratic(0.0, 2.0, -4.0).as_slice(), &[2.0]);
        // Cancellation: roots 1e-8 and 1e8.
        let r = quadratic(1.0, -(1e8 + 1e-8), 1.0);
        assert!((r.as_slice()[0] - 1e-8).abs() < 1e-22);
    }
}
