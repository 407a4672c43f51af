//! Polynomial roots against their defining polynomials.

use crate::generate;
use crate::property::{Backend, Config, Outcome};
use beam_math::roots::{cubic, quadratic, quartic};
use rand::Rng;

fn eval(c: &[f64], x: f64) -> (f64, f64) {
    c.iter().rev().fold((0.0, 0.0), |(p, b), &ci| (p * x + ci, b * x.abs() + ci.abs()))
}

fn solve(c: &[f64]) -> Vec<f64> {
    match c.len() {
        3 => quadratic(c[2], c[1], c[0]).as_slice().to_vec(),
        4 => cubic(c[3], c[2], c[1], c[0]).as_slice().to_vec(),
        _ => quartic(c[4], c[3], c[2], c[1], c[0]).as_slice().to_vec(),
    }
}

/// Expand `scale·Π(x − rᵢ)` into ascending coefficients.
fn from_roots(roots: &[f64], scale: f64) -> Vec<f64> {
    let mut c = vec![scale];
    for &r in roots {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i + 1] += ci;
            next[i] -= r * ci;
        }
        c = next;
    }
    c
}

/// Roots of quadratics, cubics and quartics: (1) 30,000 polynomials built from known roots, with
/// double, triple and nearly double roots, find every root (simple to 1e-8, double to 1e-6, triple to
/// 1e-4, relative) and nothing else; (2) 30,000 random-coefficient polynomials: every reported root
/// makes the polynomial vanish to within its rounding bound and no sign change on a fine grid is missed.
pub(super) fn roots_vs_polynomial(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(6);
    let mut worst = [0.0f64; 3];
    for i in 0..30_000 {
        let degree = rng.random_range(2..=4usize);
        let mut roots: Vec<(f64, usize)> = Vec::new();
        while roots.iter().map(|r| r.1).sum::<usize>() < degree {
            let left = degree - roots.iter().map(|r| r.1).sum::<usize>();
            let x = f64::from(generate::uniform(&mut rng, -3.0, 3.0));
            if roots.iter().any(|r| (r.0 - x).abs() < 0.05) {
                continue;
            }
            let m = match rng.random_range(0..6) {
                0 if left >= 2 => 2,
                1 if left >= 3 => 3,
                _ => 1,
            };
            roots.push((x, m));
            if m == 1 && left >= 2 && rng.random_range(0..5) == 0 {
                roots.push((x + 1e-3, 1));
            }
        }
        let flat: Vec<f64> = roots.iter().flat_map(|&(x, m)| std::iter::repeat_n(x, m)).collect();
        let scale = f64::from(generate::uniform(&mut rng, 0.1, 10.0)) * if rng.random() { 1.0 } else { -1.0 };
        let c = from_roots(&flat, scale);
        let found = solve(&c);
        if found.len() != roots.len() {
            return Err(format!("case {i}: roots {roots:?} but found {found:?}"));
        }
        for &(x, m) in &roots {
            let err = found.iter().map(|f| (f - x).abs()).fold(f64::INFINITY, f64::min) / (1.0 + x.abs());
            let tol = [1e-8, 1e-6, 1e-4][m - 1];
            worst[m - 1] = worst[m - 1].max(err);
            if err > tol {
                return Err(format!("case {i}: root {x} (multiplicity {m}) found with error {err:e}: {found:?}"));
            }
        }
    }
    for i in 0..30_000 {
        let degree = rng.random_range(2..=4usize);
        let c: Vec<f64> = (0..=degree).map(|_| f64::from(generate::uniform(&mut rng, -5.0, 5.0))).collect();
        let found = solve(&c);
        for &x in &found {
            let (p, b) = eval(&c, x);
            if p.abs() > 1e-10 * b.max(1.0) {
                return Err(format!("case {i}: p({x}) = {p:e} for {c:?}"));
            }
        }
        let mut changes = 0;
        let grid = 4_000;
        let (mut prev, _) = eval(&c, -30.0);
        for k in 1..=grid {
            let (p, _) = eval(&c, -30.0 + 60.0 * k as f64 / grid as f64);
            if (p < 0.0) != (prev < 0.0) && p != 0.0 && prev != 0.0 {
                changes += 1;
            }
            prev = p;
        }
        if changes > found.len() {
            return Err(format!("case {i}: {changes} sign changes but roots {found:?} of {c:?}"));
        }
    }
    Ok(Outcome {
        cases: 60_000,
        note: format!(
            "worst relative error: simple {:.1e}, double {:.1e}, triple {:.1e}",
            worst[0], worst[1], worst[2]
        ),
    })
}
