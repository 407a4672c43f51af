//! Volume under the normalised 2D Gaussian `ρ(φ) = e^{−‖φ‖²/2σ²}/(2πσ²)` over a triangular domain
//! `ABC` of the scatter-angle plane (002 §4.2): exactly, through Owen's T function, and as the
//! paper's tessellated estimate (Figs. 11 and 12).

use crate::float::Float;
use glam::{DVec2, Vec2};

/// Five-point Gauss–Legendre nodes and weights on `[−1, 1]`.
const GL5: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// Standard normal distribution function `Φ(x)`.
fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / core::f64::consts::SQRT_2)
}

/// Owen's T function `T(h, a) = (1/2π) ∫₀ᵃ e^{−h²(1+x²)/2}/(1+x²) dx` for `h ≥ 0`, any `a`
/// (odd in `a`). For `|a| ≤ 1`: composite five-point Gauss–Legendre on up to 3 panels over the
/// part of `[0, a]` where the integrand is not negligible (error below 1e-12);
/// for `|a| > 1`: `T(h,a) = ½Φ(h) + ½Φ(ah) − Φ(h)Φ(ah) − T(ah, 1/a)`.
#[must_use]
pub fn owens_t(h: f64, a: f64) -> f64 {
    if a < 0.0 {
        return -owens_t(h, -a);
    }
    let h = h.abs();
    if a == 0.0 {
        return 0.0;
    }
    if a > 1.0 {
        if !a.is_finite() {
            return 0.5 * (1.0 - normal_cdf(h));
        }
        let ah = a * h;
        return 0.5 * normal_cdf(h) + 0.5 * normal_cdf(ah) - normal_cdf(h) * normal_cdf(ah) - owens_t(ah, 1.0 / a);
    }
    if h > 40.0 {
        return 0.0;
    }
    // Past x = √80/h the integrand is below e^{−40} of its start: integrate up to there, on panels
    // at most 1/3 wide and at most 3 of the Gaussian factor's widths (1/h) wide, so at most 3.
    let upper = if h * a > 8.95 { 8.95 / h } else { a };
    // ⌈v⌉ without `ceil` (not in core), at least 1.
    let panels = 1 + ((h * upper / 3.0).max(3.0 * upper) * (1.0 - 1e-12)) as usize;
    let width = upper / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = (p as f64 + 0.5) * width;
        for &(x, w) in &GL5 {
            let t = mid + 0.5 * width * x;
            let q = 1.0 + t * t;
            sum += w * (-0.5 * h * h * q).exp_() / q;
        }
    }
    sum * 0.5 * width / (2.0 * core::f64::consts::PI)
}

/// Signed Gaussian volume over the triangle `(0, a, b)` (positive when counter-clockwise), by
/// splitting at the foot of the perpendicular from the origin to line `ab`: a right triangle with
/// leg `h` and angle `α` has volume `α/2π − T(h/σ, tan α)`.
#[must_use]
pub fn sector_volume(a: DVec2, b: DVec2, sigma: f64) -> f64 {
    let e = b - a;
    let len = e.length();
    let cross = a.perp_dot(b);
    if len == 0.0 || cross == 0.0 {
        return 0.0;
    }
    let t = e / len;
    let h = cross.abs() / len;
    let foot = a - a.dot(t) * t;
    let sa = (a - foot).dot(t);
    let sb = (b - foot).dot(t);
    let g = |s: f64| s.atan2_(h) / (2.0 * core::f64::consts::PI) - owens_t(h / sigma, s / h);
    cross.signum() * (g(sb) - g(sa))
}

/// Volume under the normalised Gaussian of standard deviation `sigma` centred at the origin over
/// the triangle `abc`: `|V(0ab) + V(0bc) + V(0ca)|`. Exact to ~1e-12, continuous everywhere
/// (in particular where the origin crosses an edge: 002 §4.2's continuity requirement).
#[must_use]
pub fn gaussian_volume(a: Vec2, b: Vec2, c: Vec2, sigma: f32) -> f32 {
    let (a, b, c, s) = (a.as_dvec2(), b.as_dvec2(), c.as_dvec2(), f64::from(sigma));
    if !(s > 0.0) {
        // The specular limit: a Dirac delta at the origin.
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .map(|(p, q)| p.perp_dot(*q).signum())
            .fold((true, true), |(pos, neg), x| (pos && x >= 0.0, neg && x <= 0.0));
        return if inside.0 || inside.1 { 1.0 } else { 0.0 };
    }
    (sector_volume(a, b, s) + sector_volume(b, c, s) + sector_volume(c, a, s)).abs() as f32
}

/// Value of the normalised Gaussian at `p`.
#[must_use]
pub fn gaussian(p: Vec2, sigma: f32) -> f32 {
    let s2 = sigma * sigma;
    (-p.length_squared() / (2.0 * s2)).exp_() / (2.0 * core::f32::consts::PI * s2)
}

/// The paper's tessellated estimate (002 Figs. 11 and 12). Inside (no split point): three
/// triangles around the peak `O`, each `area × mean of ρ at its corners`,
/// `P_E = ½‖AOB·P_AOB + BOC·P_BOC + COA·P_COA‖`. Outside with a split point `D` on edge `AB`
/// (`split = Some(D)`, the edges relabelled so that the split edge is `AB`): the two triangles
/// `CAD` and `CDB`, `P_E = ½‖COA + AOD‖·P_CAD + ½‖BOC + DOB‖·P_CDB` (the paper prints `P_CAD` twice;
/// the second is `P_CDB`). Outside without a split point: `area(ABC)·P_ABC`.
#[must_use]
pub fn gaussian_volume_tessellated(a: Vec2, b: Vec2, c: Vec2, split: Option<Vec2>, sigma: f32) -> f32 {
    let p = |x: Vec2| gaussian(x, sigma);
    let area = |x: Vec2, y: Vec2, z: Vec2| 0.5 * ((y - x).perp_dot(z - x)).abs();
    let o = Vec2::ZERO;
    let inside = {
        let s = [a.perp_dot(b), b.perp_dot(c), c.perp_dot(a)];
        s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
    };
    if inside {
        let po = p(o);
        let tri = |x: Vec2, y: Vec2| 0.5 * x.perp_dot(y) * (p(x) + po + p(y)) / 3.0;
        return (tri(a, b) + tri(b, c) + tri(c, a)).abs();
    }
    match split {
        Some(d) => area(c, a, d) * (p(c) + p(a) + p(d)) / 3.0 + area(c, d, b) * (p(c) + p(d) + p(b)) / 3.0,
        None => area(a, b, c) * (p(a) + p(b) + p(c)) / 3.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owens_t_known_values() {
        // T(0, a) = atan(a)/2π; T(h, 1) = Φ(h)(1 − Φ(h))/2.
        assert!((owens_t(0.0, 0.5) - libm::atan(0.5) / (2.0 * core::f64::consts::PI)).abs() < 1e-14);
        let h = 0.7;
        assert!((owens_t(h, 1.0) - 0.5 * normal_cdf(h) * (1.0 - normal_cdf(h))).abs() < 1e-13);
        // Continuity across a = 1.
        assert!((owens_t(1.3, 1.0 - 1e-9) - owens_t(1.3, 1.0 + 1e-9)).abs() < 1e-9);
        // Against composite Simpson on the defining integral (an independent method).
        for (h, a) in [(0.5, 2.0), (2.0, 0.3), (0.1, 7.0), (3.0, 1.5)] {
            let n = 20_000;
            let f = |x: f64| libm::exp(-0.5 * h * h * (1.0 + x * x)) / (1.0 + x * x);
            let mut s = f(0.0) + f(a);
            for i in 1..n {
                s += f(a * i as f64 / n as f64) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            let simpson = s * a / n as f64 / 3.0 / (2.0 * core::f64::consts::PI);
            assert!((owens_t(h, a) - simpson).abs() < 1e-12, "T({h}, {a}) = {} vs {simpson}", owens_t(h, a));
        }
    }

    #[test]
    fn whole_plane_and_half_plane() {
        let big = 1e3;
        let v = gaussian_volume(Vec2::new(-big, -big), Vec2::new(big, -big), Vec2::new(0.0, big), 1.0);
        assert!((v - 1.0).abs() < 1e-6);
        // A huge triangle with the origin on an edge: half the mass.
        let v = gaussian_volume(Vec2::new(-big, 0.0), Vec2::new(big, 0.0), Vec2::new(0.0, big), 1.0);
        assert!((v - 0.5).abs() < 1e-5, "{v}");
    }

    #[test]
    fn tessellated_is_continuous_at_the_boundary() {
        // Origin on edge AB at its midpoint: the inside formula and the split formula (D = O) agree.
        let (a, b, c) = (Vec2::new(-0.5, 0.0), Vec2::new(0.5, 0.0), Vec2::new(0.1, 0.8));
        let inside = gaussian_volume_tessellated(a, b, c, None, 0.5);
        let outside = gaussian_volume_tessellated(a, b, c, Some(Vec2::ZERO), 0.5);
        assert!((inside - outside).abs() < 1e-6, "{inside} {outside}");
    }
}
