//! Convex polygons in the plane with a fixed capacity (no allocation): shoelace area (004 App. A.10),
//! vertex ordering by `atan2` about the barycentre (A.9.3), segment intersection (A.9.2), the
//! overlap of two convex polygons (A.9), half-plane clipping (Sutherland–Hodgman) and convex hulls.

use glam::Vec2;

use crate::float::Float;

/// A polygon operation needed more vertices than the fixed capacity holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CapacityExceeded;

/// A convex polygon of at most `N` vertices, stored inline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvexPolygon<const N: usize> {
    verts: [Vec2; N],
    len: usize,
}

impl<const N: usize> Default for ConvexPolygon<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> ConvexPolygon<N> {
    /// The capacity `N`.
    pub const CAPACITY: usize = N;

    /// An empty polygon.
    #[must_use]
    pub const fn new() -> Self {
        Self { verts: [Vec2::ZERO; N], len: 0 }
    }

    /// A polygon from vertices in order; fails when there are more than `N`.
    pub fn from_slice(points: &[Vec2]) -> Result<Self, CapacityExceeded> {
        let mut p = Self::new();
        for &v in points {
            p.push(v)?;
        }
        Ok(p)
    }

    /// Append a vertex.
    pub fn push(&mut self, v: Vec2) -> Result<(), CapacityExceeded> {
        if self.len == N {
            return Err(CapacityExceeded);
        }
        self.verts[self.len] = v;
        self.len += 1;
        Ok(())
    }

    /// The vertices in order.
    #[must_use]
    pub fn vertices(&self) -> &[Vec2] {
        &self.verts[..self.len]
    }

    /// Number of vertices.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there are no vertices.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Signed shoelace area, positive for counter-clockwise order (004 App. A.10).
    #[must_use]
    pub fn signed_area(&self) -> f32 {
        signed_area(self.vertices())
    }

    /// Shoelace area (004 App. A.10).
    #[must_use]
    pub fn area(&self) -> f32 {
        self.signed_area().abs()
    }

    /// Bounding rectangle `(lo, hi)` of the vertices (`(+∞, −∞)` when empty).
    #[must_use]
    pub fn bounds(&self) -> (Vec2, Vec2) {
        self.vertices().iter().fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), v| (lo.min(*v), hi.max(*v)))
    }

    /// Mean of the vertices.
    #[must_use]
    pub fn centroid(&self) -> Vec2 {
        if self.len == 0 { Vec2::ZERO } else { self.vertices().iter().sum::<Vec2>() / self.len as f32 }
    }

    /// Split by the line through `a` with normal `n` into the part where `n·(x − a) ≤ 0` (inside)
    /// and the part where it is `≥ 0` (outside), Sutherland–Hodgman style, one edge at a time.
    /// Vertices with `|n·(x − a)| ≤ eps` count on both sides (the fuzzy test of 001 App. A).
    pub fn split(&self, a: Vec2, n: Vec2, eps: f32) -> Result<(Self, Self), CapacityExceeded> {
        let mut outside = Self::new();
        let inside = self.sides::<true>(a, n, eps, &mut outside)?;
        Ok((inside, outside))
    }

    /// Keep the part on the inner side `n·(x − a) ≤ 0` of a line: the inside part of
    /// [`ConvexPolygon::split`] with `eps = 0`, without building the outside part (the pixel
    /// coverage clips each pixel an edge crosses).
    pub fn clip(&self, a: Vec2, n: Vec2) -> Result<Self, CapacityExceeded> {
        self.sides::<false>(a, n, 0.0, &mut Self::new())
    }

    /// The inside part of [`ConvexPolygon::split`], returned, and with `OUTSIDE` its outside part
    /// in `outside` (an empty polygon).
    fn sides<const OUTSIDE: bool>(
        &self,
        a: Vec2,
        n: Vec2,
        eps: f32,
        outside: &mut Self,
    ) -> Result<Self, CapacityExceeded> {
        let mut inside = Self::new();
        let v = self.vertices();
        for i in 0..v.len() {
            let p = v[i];
            let q = v[(i + 1) % v.len()];
            let dp = n.dot(p - a);
            let dq = n.dot(q - a);
            if dp <= eps {
                inside.push(p)?;
            }
            if OUTSIDE && dp >= -eps {
                outside.push(p)?;
            }
            if (dp < -eps && dq > eps) || (dp > eps && dq < -eps) {
                let x = p + (q - p) * (dp / (dp - dq));
                inside.push(x)?;
                if OUTSIDE {
                    outside.push(x)?;
                }
            }
        }
        if inside.len < 3 {
            inside = Self::new();
        }
        if OUTSIDE && outside.len < 3 {
            *outside = Self::new();
        }
        Ok(inside)
    }

    /// Intersection with another convex polygon by clipping against each of its edges
    /// (Sutherland–Hodgman). `other` may have either winding.
    pub fn clip_by<const M: usize>(&self, other: &ConvexPolygon<M>) -> Result<Self, CapacityExceeded> {
        let w = other.vertices();
        let sign = if other.signed_area() >= 0.0 { 1.0 } else { -1.0 };
        let mut out = *self;
        for i in 0..w.len() {
            let e = w[(i + 1) % w.len()] - w[i];
            // Outward normal of a counter-clockwise edge is (e.y, −e.x).
            out = out.clip(w[i], sign * Vec2::new(e.y, -e.x))?;
            if out.is_empty() {
                break;
            }
        }
        Ok(out)
    }

    /// Intersection of two convex polygons as in 004 App. A.9: the vertices of each inside the other
    /// (A.9.1), the pairwise edge intersections (A.9.2), then `atan2` ordering (A.9.3).
    pub fn intersect<const M: usize>(&self, other: &ConvexPolygon<M>) -> Result<Self, CapacityExceeded> {
        let (a, b) = (self.vertices(), other.vertices());
        let mut out = Self::new();
        let mut add = |p: Vec2| -> Result<(), CapacityExceeded> {
            if out.vertices().iter().all(|q| q.distance_squared(p) > 1e-12 * (1.0 + p.length_squared())) {
                out.push(p)?;
            }
            Ok(())
        };
        for &p in a {
            if point_in_or_on(p, b) {
                add(p)?;
            }
        }
        for &p in b {
            if point_in_or_on(p, a) {
                add(p)?;
            }
        }
        for i in 0..a.len() {
            for j in 0..b.len() {
                if let Some(k) = segment_intersection(a[i], a[(i + 1) % a.len()], b[j], b[(j + 1) % b.len()]) {
                    add(k)?;
                }
            }
        }
        if out.len < 3 {
            return Ok(Self::new());
        }
        let n = out.len;
        order_ccw(&mut out.verts[..n]);
        Ok(out)
    }
}

/// Signed shoelace area `½ Σ (x_i y_{i+1} − y_i x_{i+1})` (004 App. A.10), evaluated relative to
/// the first vertex: the same sum, without the cancellation that absolute coordinates cause for a
/// small polygon far from the origin (a pixel of an image plane).
#[must_use]
pub fn signed_area(points: &[Vec2]) -> f32 {
    let n = points.len();
    if n < 3 {
        return 0.0;
    }
    let o = points[0];
    let mut s = 0.0;
    for i in 1..n - 1 {
        s += (points[i] - o).perp_dot(points[i + 1] - o);
    }
    0.5 * s
}

/// Shoelace area (004 App. A.10).
#[must_use]
pub fn shoelace_area(points: &[Vec2]) -> f32 {
    signed_area(points).abs()
}

/// Sort the vertices of a convex polygon counter-clockwise by `atan2` of their offset from the
/// barycentre (004 App. A.9.3).
pub fn order_ccw(points: &mut [Vec2]) {
    if points.is_empty() {
        return;
    }
    let o = points.iter().sum::<Vec2>() / points.len() as f32;
    points.sort_unstable_by(|p, q| {
        let a = (p.y - o.y).atan2_(p.x - o.x);
        let b = (q.y - o.y).atan2_(q.x - o.x);
        a.total_cmp(&b)
    });
}

/// Intersection point of segments `MN` and `PQ` through the line equations `Ax + By = C`
/// (004 App. A.9.2). `None` for parallel lines or when the point lies outside either segment.
#[must_use]
pub fn segment_intersection(m: Vec2, n: Vec2, p: Vec2, q: Vec2) -> Option<Vec2> {
    let line = |p: Vec2, q: Vec2| {
        let a = q.y - p.y;
        let b = p.x - q.x;
        (a, b, a * p.x + b * p.y)
    };
    let (a1, b1, c1) = line(m, n);
    let (a2, b2, c2) = line(p, q);
    let det = a1 * b2 - a2 * b1;
    if det == 0.0 {
        return None;
    }
    let k = Vec2::new((b2 * c1 - b1 * c2) / det, (a1 * c2 - a2 * c1) / det);
    let within = |u: Vec2, v: Vec2| {
        let tol = 1e-5 * (1.0 + u.abs().max(v.abs()).max_element());
        u.min(v).x - tol <= k.x && u.max(v).x + tol >= k.x && u.min(v).y - tol <= k.y && u.max(v).y + tol >= k.y
    };
    (within(m, n) && within(p, q)).then_some(k)
}

/// Inside-or-on test for either winding (the closed form of Alg. A.4, for the overlap algorithm).
fn point_in_or_on(p: Vec2, hull: &[Vec2]) -> bool {
    let n = hull.len();
    if n < 3 {
        return false;
    }
    let s = signed_area(hull).signum();
    let scale = hull.iter().fold(0.0f32, |m, v| m.max(v.abs().max_element())).max(p.abs().max_element());
    let tol = 1e-6 * scale * scale;
    (0..n).all(|i| s * (hull[(i + 1) % n] - hull[i]).perp_dot(p - hull[i]) >= -tol)
}

/// Convex hull of at most `N` points (Andrew's monotone chain), counter-clockwise, collinear points
/// dropped.
#[must_use]
pub fn convex_hull<const N: usize>(points: &[Vec2]) -> ConvexPolygon<N> {
    let mut sorted = [Vec2::ZERO; N];
    let m = points.len().min(N);
    sorted[..m].copy_from_slice(&points[..m]);
    let sorted = &mut sorted[..m];
    sorted.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let mut hull = [Vec2::ZERO; N];
    let mut k = 0usize;
    // Lower hull then upper hull; the hull of m points has at most m vertices + 1 transiently,
    // so work in a buffer of 2N and copy.
    let mut buf = [[Vec2::ZERO; N]; 2];
    let flat = buf.as_flattened_mut();
    for &p in sorted.iter() {
        while k >= 2 && crate::shapes::orient2d(flat[k - 2], flat[k - 1], p) <= 0.0 {
            k -= 1;
        }
        flat[k] = p;
        k += 1;
    }
    let lower = k + 1;
    for &p in sorted.iter().rev().skip(1) {
        while k >= lower && crate::shapes::orient2d(flat[k - 2], flat[k - 1], p) <= 0.0 {
            k -= 1;
        }
        flat[k] = p;
        k += 1;
    }
    let count = k.saturating_sub(1).min(N);
    hull[..count].copy_from_slice(&flat[..count]);
    ConvexPolygon { verts: hull, len: if count >= 3 { count } else { 0 } }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Poly = ConvexPolygon<8>;

    fn square(o: Vec2, s: f32) -> Poly {
        Poly::from_slice(&[o, o + Vec2::new(s, 0.0), o + Vec2::splat(s), o + Vec2::new(0.0, s)]).unwrap()
    }

    #[test]
    fn shoelace_hand_worked() {
        assert_eq!(square(Vec2::ZERO, 2.0).area(), 4.0);
        assert_eq!(shoelace_area(&[Vec2::ZERO, Vec2::new(4.0, 0.0), Vec2::new(0.0, 3.0)]), 6.0);
        let mut cw = [Vec2::ZERO, Vec2::new(0.0, 3.0), Vec2::new(4.0, 0.0)];
        assert_eq!(signed_area(&cw), -6.0);
        order_ccw(&mut cw);
        assert_eq!(signed_area(&cw), 6.0);
    }

    /// `clip` is `split`'s inside part with `eps = 0` (bit for bit) wherever `split` fits, and
    /// also fits where only `split`'s outside part would not: a full polygon whose corner is kept.
    #[test]
    fn clip_is_the_inside_of_split() {
        // Regular polygons of 3 to 8 corners, cut by lines at many angles and offsets.
        let mut seed = 12345u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            f32::from(u16::try_from(seed >> 16).unwrap_or(0)) / 65536.0
        };
        for k in 3..=8usize {
            let corners: Vec<Vec2> = (0..k)
                .map(|i| {
                    let t = core::f32::consts::TAU * i as f32 / k as f32;
                    Vec2::new(libm::cosf(t), libm::sinf(t))
                })
                .collect();
            let poly = Poly::from_slice(&corners).unwrap();
            for _ in 0..200 {
                let t = core::f32::consts::TAU * next();
                let (n, a) = (Vec2::new(libm::cosf(t), libm::sinf(t)), Vec2::splat(2.0 * next() - 1.0));
                if let Ok((inside, _)) = poly.split(a, n, 0.0) {
                    assert_eq!(poly.clip(a, n), Ok(inside));
                }
            }
            if k == 8 {
                // The corner at (1, 0) kept: a triangle inside, 9 corners outside (past 8).
                let (a, n) = (Vec2::new(0.99, 0.0), -Vec2::X);
                assert!(poly.split(a, n, 0.0).is_err());
                assert_eq!(poly.clip(a, n).map(|c| c.len()), Ok(3));
            }
        }
    }

    #[test]
    fn overlapping_squares() {
        let a = square(Vec2::ZERO, 2.0);
        let b = square(Vec2::ONE, 2.0);
        let i = a.intersect(&b).unwrap();
        assert!((i.area() - 1.0).abs() < 1e-6, "{i:?}");
        let c = a.clip_by(&b).unwrap();
        assert!((c.area() - 1.0).abs() < 1e-6);
        assert!(a.intersect(&square(Vec2::splat(5.0), 1.0)).unwrap().is_empty());
    }

    #[test]
    fn split_conserves_area() {
        let a = square(Vec2::ZERO, 2.0);
        let (i, o) = a.split(Vec2::new(0.5, 0.0), Vec2::X, 0.0).unwrap();
        assert!((i.area() - 1.0).abs() < 1e-6 && (o.area() - 3.0).abs() < 1e-6);
        // A line through a corner within eps does not split.
        let (i, o) = a.split(Vec2::new(2.0, 2.0), Vec2::new(1.0, 1.0).normalize(), 1e-4).unwrap();
        assert!((i.area() - 4.0).abs() < 1e-6 && o.is_empty());
    }

    #[test]
    fn segments() {
        let k = segment_intersection(Vec2::ZERO, Vec2::splat(2.0), Vec2::new(0.0, 2.0), Vec2::new(2.0, 0.0));
        assert_eq!(k, Some(Vec2::ONE));
        assert_eq!(segment_intersection(Vec2::ZERO, Vec2::ONE, Vec2::new(3.0, 0.0), Vec2::new(0.0, 3.0)), None);
    }

    #[test]
    fn hull_of_square_with_interior_points() {
        let pts = [Vec2::ZERO, Vec2::splat(0.5), Vec2::X, Vec2::ONE, Vec2::new(0.2, 0.7), Vec2::Y];
        let h: ConvexPolygon<8> = convex_hull(&pts);
        assert_eq!(h.len(), 4);
        assert!((h.signed_area() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn capacity_is_reported() {
        let tri = ConvexPolygon::<3>::from_slice(&[Vec2::ZERO, Vec2::X, Vec2::Y]).unwrap();
        assert_eq!(tri.split(Vec2::new(0.2, 0.0), Vec2::X, 0.0), Err(CapacityExceeded));
    }
}
