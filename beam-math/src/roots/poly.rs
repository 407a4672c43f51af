//! Shared machinery: the root list, evaluation with an error bound and bracketed refinement.

/// Distinct real roots in ascending order, at most `N`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roots<const N: usize> {
    values: [f64; N],
    len: usize,
}

impl<const N: usize> Default for Roots<N> {
    fn default() -> Self {
        Self { values: [0.0; N], len: 0 }
    }
}

impl<const N: usize> Roots<N> {
    /// The roots, ascending.
    #[must_use]
    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.len]
    }

    /// Number of distinct real roots.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there is no real root.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Insert keeping ascending order, skipping a value equal to a neighbour within `tol`.
    pub(crate) fn insert(&mut self, x: f64, tol: f64) {
        if !x.is_finite() || self.len == N {
            return;
        }
        if self.as_slice().iter().any(|&r| (r - x).abs() <= tol) {
            return;
        }
        let mut i = self.len;
        while i > 0 && self.values[i - 1] > x {
            self.values[i] = self.values[i - 1];
            i -= 1;
        }
        self.values[i] = x;
        self.len += 1;
    }

    pub(crate) fn from_slice(xs: &[f64]) -> Self {
        let mut r = Self::default();
        for &x in xs {
            r.insert(x, 0.0);
        }
        r
    }
}

/// `p(x)` for coefficients in ascending order, with the running error bound `Σ |c_i| |x|^i`.
#[inline]
pub(crate) fn eval(c: &[f64], x: f64) -> (f64, f64) {
    let mut p = 0.0;
    let mut bound = 0.0;
    for &ci in c.iter().rev() {
        p = p * x + ci;
        bound = bound * x.abs() + ci.abs();
    }
    (p, bound)
}

/// `p(x)` and `p'(x)` by Horner.
#[inline]
fn eval_d(c: &[f64], x: f64) -> (f64, f64) {
    let mut p = 0.0;
    let mut d = 0.0;
    for &ci in c.iter().rev() {
        d = d * x + p;
        p = p * x + ci;
    }
    (p, d)
}

/// Cauchy bound: every root has `|x| ≤ 1 + max |c_i / c_n|`.
pub(crate) fn cauchy_bound(c: &[f64]) -> f64 {
    let n = c.len() - 1;
    1.0 + c[..n].iter().fold(0.0f64, |m, &ci| m.max((ci / c[n]).abs()))
}

/// The unique root of a polynomial monotone on `[lo, hi]` with `p(lo)·p(hi) < 0`, by Newton steps
/// kept inside a shrinking bracket (bisection when Newton leaves it), from the first of `guesses`
/// strictly inside the bracket, else from its midpoint.
fn refine(c: &[f64], mut lo: f64, mut hi: f64, guesses: &[f64]) -> f64 {
    let (plo, _) = eval_d(c, lo);
    let rising = plo < 0.0;
    let mut x = guesses.iter().copied().find(|&g| g > lo && g < hi).unwrap_or(0.5 * (lo + hi));
    for _ in 0..200 {
        let (p, d) = eval_d(c, x);
        if p == 0.0 {
            return x;
        }
        if (p < 0.0) == rising {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - p / d;
        let next = if d != 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        if (next - x).abs() <= 4.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE)
            || hi - lo <= 2.0 * f64::EPSILON * lo.abs().max(hi.abs())
        {
            return next;
        }
        x = next;
    }
    x
}

/// Roots of `c` (degree ≥ 2, ascending coefficients, non-zero leading one) given its sorted
/// critical points `crit` (the distinct real roots of the derivative) and approximate roots
/// `guesses` to start the refinement from (any values: a bracket without one starts at its middle).
pub(crate) fn roots_from_critical<const N: usize>(c: &[f64], crit: &[f64], guesses: &[f64]) -> Roots<N> {
    let mut out = Roots::<N>::default();
    let bound = cauchy_bound(c);
    let mut points = [0.0f64; 6];
    let mut m = 0;
    points[m] = -bound;
    m += 1;
    for &x in crit {
        points[m] = x.clamp(-bound, bound);
        m += 1;
    }
    points[m] = bound;
    m += 1;
    let values: [(f64, f64); 6] = core::array::from_fn(|i| if i < m { eval(c, points[i]) } else { (0.0, 0.0) });
    // Multiple roots: a critical point where |p| is within its rounding error.
    for i in 1..m - 1 {
        let (p, b) = values[i];
        if p.abs() <= 32.0 * f64::EPSILON * b {
            out.insert(points[i], 0.0);
        }
    }
    for i in 0..m - 1 {
        let (pa, ba) = values[i];
        let (pb, bb) = values[i + 1];
        let za = pa.abs() <= 32.0 * f64::EPSILON * ba;
        let zb = pb.abs() <= 32.0 * f64::EPSILON * bb;
        if !za && !zb && (pa < 0.0) != (pb < 0.0) {
            let x = refine(c, points[i], points[i + 1], guesses);
            out.insert(x, 0.0);
        }
    }
    // Merge numerically coincident roots (a double root may also be bracketed on one side).
    let mut merged = Roots::default();
    for &x in out.as_slice() {
        merged.insert(x, 1e-12 * (1.0 + x.abs()));
    }
    merged
}
