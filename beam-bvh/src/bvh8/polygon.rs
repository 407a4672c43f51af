//! Convex polygons cut by axis planes (Sutherland–Hodgman): the pieces of a triangle that
//! pre-splitting and spatial splits bound.

use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};

/// Most vertices of a clipped piece: a triangle cut by up to 13 planes.
pub(super) const MAX_VERTICES: usize = 16;

/// A convex polygon in 3D (a triangle, clipped).
#[derive(Clone, Copy)]
pub(super) struct Polygon {
    pub v: [Vec3; MAX_VERTICES],
    pub len: usize,
}

impl Polygon {
    pub(super) fn triangle(t: &Triangle) -> Self {
        let mut v = [Vec3::ZERO; MAX_VERTICES];
        v[..3].copy_from_slice(&t.v);
        Self { v, len: 3 }
    }

    pub(super) fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.v[..self.len])
    }

    fn push(&mut self, p: Vec3) {
        if self.len < MAX_VERTICES {
            self.v[self.len] = p;
            self.len += 1;
        }
    }

    /// The parts with coordinate `axis` at most and at least `plane` (Sutherland–Hodgman); new
    /// vertices lie exactly on the plane along `axis`.
    pub(super) fn cut(&self, axis: usize, plane: f32) -> (Self, Self) {
        let empty = Self { v: [Vec3::ZERO; MAX_VERTICES], len: 0 };
        let (mut left, mut right) = (empty, empty);
        for i in 0..self.len {
            let (a, b) = (self.v[i], self.v[(i + 1) % self.len]);
            let (da, db) = (a[axis] - plane, b[axis] - plane);
            if da <= 0.0 {
                left.push(a);
            }
            if da >= 0.0 {
                right.push(a);
            }
            if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
                let mut x = a + (b - a) * (da / (da - db));
                x[axis] = plane;
                left.push(x);
                right.push(x);
            }
        }
        (left, right)
    }
}
