//! A frustum (a pyramid cut by two parallel planes) given by its eight corners; the volume of a
//! camera, of a 4-corner polygon beam of 001, or of any perspective projection.

use crate::shapes::{Aabb, Plane};
use glam::{Mat4, Vec3, Vec4};

/// A frustum by corners. `near[i]` and `far[i]` lie on the same edge ray, in counter-clockwise order
/// seen from the apex looking along the frustum; near and far quads are parallel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    /// Corners of the near face.
    pub near: [Vec3; 4],
    /// Corners of the far face.
    pub far: [Vec3; 4],
}

impl Frustum {
    /// The frustum of the rays from `apex` through `dirs` (counter-clockwise seen along the rays),
    /// between the distances `near` and `far` measured along `axis` (unit length).
    #[must_use]
    pub fn from_apex(apex: Vec3, dirs: [Vec3; 4], axis: Vec3, near: f32, far: f32) -> Self {
        let at = |s: f32| dirs.map(|d| apex + d * (s / d.dot(axis)));
        Self { near: at(near), far: at(far) }
    }

    /// The frustum of a view-projection matrix whose clip volume is `−w ≤ x, y ≤ w`, `0 ≤ z ≤ w`
    /// (the wgpu / glam `perspective_rh` convention).
    #[must_use]
    pub fn from_view_projection(m: Mat4) -> Self {
        let inv = m.inverse();
        let corner = |x: f32, y: f32, z: f32| {
            let p = inv * Vec4::new(x, y, z, 1.0);
            p.truncate() / p.w
        };
        let quad = |z: f32| [corner(-1.0, -1.0, z), corner(1.0, -1.0, z), corner(1.0, 1.0, z), corner(-1.0, 1.0, z)];
        Self { near: quad(0.0), far: quad(1.0) }
    }

    /// The bounding box of the eight corners, used by the rejection test (004 App. A.5).
    #[must_use]
    pub fn aabb(&self) -> Aabb {
        self.near.iter().chain(self.far.iter()).fold(Aabb::EMPTY, |b, &p| b.grow(p))
    }

    /// The six face planes with normals pointing outwards: near, far, then the four sides.
    #[must_use]
    pub fn planes(&self) -> [Plane; 6] {
        let c = self.center();
        let outward = |a: Vec3, b: Vec3, d: Vec3| {
            let p = Plane::from_points(a, b, d);
            if p.eval(c) > 0.0 { Plane { normal: -p.normal, d: -p.d } } else { p }
        };
        let (n, f) = (&self.near, &self.far);
        [
            outward(n[0], n[1], n[2]),
            outward(f[0], f[1], f[2]),
            outward(n[0], n[1], f[1]),
            outward(n[1], n[2], f[2]),
            outward(n[2], n[3], f[3]),
            outward(n[3], n[0], f[0]),
        ]
    }

    /// Mean of the eight corners (an interior point).
    #[must_use]
    pub fn center(&self) -> Vec3 {
        (self.near.iter().sum::<Vec3>() + self.far.iter().sum::<Vec3>()) / 8.0
    }

    /// Distinct edge directions: the quad edges (parallel ones dropped, so a rectangular frustum has
    /// two) and the four side edges (004 App. A.5: six for a camera frustum).
    #[must_use]
    pub fn edge_directions(&self) -> ([Vec3; 8], usize) {
        let mut out = [Vec3::ZERO; 8];
        let mut n = 0;
        let mut push = |e: Vec3| {
            let parallel = out[..n]
                .iter()
                .any(|o: &Vec3| o.cross(e).length_squared() <= 1e-10 * o.length_squared() * e.length_squared());
            if !parallel && e.length_squared() > 0.0 {
                out[n] = e;
                n += 1;
            }
        };
        for i in 0..4 {
            push(self.near[(i + 1) % 4] - self.near[i]);
        }
        for i in 0..4 {
            push(self.far[i] - self.near[i]);
        }
        (out, n)
    }
}
