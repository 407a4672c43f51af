//! Plain geometric types shared by every module: rays, boxes, planes and triangles.

use glam::{Vec2, Vec3};

/// A ray `r(t) = origin + t·direction` (004 App. A.1). The direction need not be normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Ray origin `O`.
    pub origin: Vec3,
    /// Ray direction `d`.
    pub direction: Vec3,
}

impl Ray {
    /// A ray from an origin and a direction.
    #[must_use]
    pub const fn new(origin: Vec3, direction: Vec3) -> Self {
        Self { origin, direction }
    }

    /// The point `O + t·d`.
    #[must_use]
    pub fn at(self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }
}

/// An axis-aligned bounding box in min–max form (004 App. A.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Default for Aabb {
    /// The empty box.
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The empty box: `min = +∞`, `max = −∞`, the identity of [`Aabb::union`].
    pub const EMPTY: Self = Self { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    /// A box from its two corners.
    #[must_use]
    pub const fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The smallest box containing every point.
    #[must_use]
    #[inline]
    pub fn from_points(points: &[Vec3]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| b.grow(p))
    }

    /// This box grown to contain `p`.
    #[must_use]
    #[inline]
    pub fn grow(self, p: Vec3) -> Self {
        Self { min: self.min.min(p), max: self.max.max(p) }
    }

    /// The smallest box containing both boxes.
    #[must_use]
    pub fn union(self, other: Self) -> Self {
        Self { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// True when `min ≤ max` on every axis.
    #[must_use]
    pub fn is_valid(self) -> bool {
        self.min.cmple(self.max).all()
    }

    /// Centre of the box.
    #[must_use]
    pub fn center(self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Edge lengths `max − min`.
    #[must_use]
    pub fn extent(self) -> Vec3 {
        self.max - self.min
    }

    /// The eight corners, index bit 0 = x, bit 1 = y, bit 2 = z (0 → min, 1 → max).
    #[must_use]
    pub fn corners(self) -> [Vec3; 8] {
        core::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}

/// A plane `n·x + d = 0` (004 App. A.2). `normal` need not be unit length unless a method says so.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Plane normal `n = [A, B, C]`.
    pub normal: Vec3,
    /// Offset `D = −n·P` for a point `P` on the plane.
    pub d: f32,
}

impl Plane {
    /// The plane through `point` with normal `normal`: `D = −⟨n·P⟩` (004 App. A.2).
    #[must_use]
    pub fn from_point_normal(point: Vec3, normal: Vec3) -> Self {
        Self { normal, d: -normal.dot(point) }
    }

    /// The plane through three points, normal `(b − a) × (c − a)` (not normalised).
    #[must_use]
    pub fn from_points(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self::from_point_normal(a, (b - a).cross(c - a))
    }

    /// `n·p + d`: the signed distance times `|n|`.
    #[must_use]
    pub fn eval(self, p: Vec3) -> f32 {
        self.normal.dot(p) + self.d
    }
}

/// A triangle given by its three vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Vertices in order; the front face is counter-clockwise seen from the normal.
    pub v: [Vec3; 3],
}

impl Triangle {
    /// A triangle from three vertices.
    #[must_use]
    pub const fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self { v: [a, b, c] }
    }

    /// `(v1 − v0) × (v2 − v0)`: twice the area times the unit normal.
    #[must_use]
    #[inline]
    pub fn scaled_normal(self) -> Vec3 {
        (self.v[1] - self.v[0]).cross(self.v[2] - self.v[0])
    }

    /// Triangle area.
    #[must_use]
    pub fn area(self) -> f32 {
        0.5 * self.scaled_normal().length()
    }

    /// The point with barycentric coordinates `w` (`w.x + w.y + w.z = 1`).
    #[must_use]
    pub fn point(self, w: Vec3) -> Vec3 {
        w.x * self.v[0] + w.y * self.v[1] + w.z * self.v[2]
    }

    /// Barycentric coordinates of `p` projected onto the triangle's plane (`Ω(P, Δ)` of 000 Alg. 3).
    /// Returns `None` for a degenerate triangle.
    #[must_use]
    pub fn barycentric(self, p: Vec3) -> Option<Vec3> {
        let n = self.scaled_normal();
        let nn = n.length_squared();
        if !(nn > 0.0) || !nn.is_finite() {
            return None;
        }
        let w0 = (self.v[1] - p).cross(self.v[2] - p).dot(n) / nn;
        let w1 = (self.v[2] - p).cross(self.v[0] - p).dot(n) / nn;
        Some(Vec3::new(w0, w1, 1.0 - w0 - w1))
    }

    /// True when every coordinate is finite and the area is positive. Without branches: BVH
    /// builders test every input triangle.
    #[must_use]
    #[inline]
    pub fn is_valid(self) -> bool {
        let n = self.scaled_normal();
        let [a, b, c] = self.v.map(Vec3::is_finite_mask);
        (a & b & c & n.is_finite_mask()).all() & (n.length_squared() > 0.0)
    }
}

/// Twice the signed area of the 2D triangle `abc` (positive when counter-clockwise).
#[must_use]
pub fn orient2d(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    (b - a).perp_dot(c - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The branch-free test is the definition: every coordinate finite, the normal finite and
    /// not zero, on zero, tiny, huge, infinite and NaN coordinates.
    #[test]
    fn is_valid_is_its_definition() {
        let values = [0.0, 1.0, -2.5, 1e-30, 1e19, -1e20, 3e38, f32::MAX, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        let mut s = 3u32;
        let mut pick = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            values[(s >> 16) as usize % values.len()]
        };
        let mut valid = 0;
        for _ in 0..200_000 {
            let mut v = || Vec3::new(pick(), pick(), pick());
            let t = Triangle::new(v(), v(), v());
            let n = t.scaled_normal();
            let want = t.v.iter().all(|v| v.is_finite()) && n.is_finite() && n.length_squared() > 0.0;
            assert_eq!(t.is_valid(), want, "{t:?}");
            valid += usize::from(want);
        }
        assert!(valid > 100, "the test made valid triangles too: {valid}");
    }
}
