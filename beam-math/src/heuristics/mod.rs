//! Cost-model areas for BVH construction (004): the surface area of a box (SAH) and its projected
//! area under an orthographic or a perspective projection (PAH).

use crate::collide::{ConvexPolygon, convex_hull};
use crate::shapes::Aabb;
use glam::{Vec2, Vec3};

/// Surface area `2(xy + yz + zx)` of a box; 0 for an empty box.
#[must_use]
pub fn surface_area(aabb: Aabb) -> f32 {
    let e = aabb.extent().max(Vec3::ZERO);
    2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
}

/// An orthonormal pair spanning the plane perpendicular to the unit vector `dir`.
fn plane_basis(dir: Vec3) -> (Vec3, Vec3) {
    let u = dir.any_orthonormal_vector();
    (u, dir.cross(u))
}

/// Area of the box's shadow on a plane perpendicular to `dir` (a parallel ray bundle, such as an
/// area light seen from afar; 004 §1): the convex hull of the 8 projected corners, by shoelace.
#[must_use]
pub fn projected_area_orthographic(aabb: Aabb, dir: Vec3) -> f32 {
    let Some(dir) = dir.try_normalize() else {
        return 0.0;
    };
    let (u, v) = plane_basis(dir);
    let pts = aabb.corners().map(|c| Vec2::new(c.dot(u), c.dot(v)));
    let hull: ConvexPolygon<8> = convex_hull(&pts);
    hull.area()
}

/// Area of the box's perspective image on the plane at unit distance from `eye` perpendicular to
/// `forward` (a pencil of rays through a point: a point light or a camera; 004 §1): the hull of the
/// projected corners, by shoelace. `None` when a corner is not in front of the eye (the box
/// straddles the eye plane and the image is unbounded).
#[must_use]
pub fn projected_area_perspective(aabb: Aabb, eye: Vec3, forward: Vec3) -> Option<f32> {
    let forward = forward.try_normalize()?;
    let (u, v) = plane_basis(forward);
    let mut pts = [Vec2::ZERO; 8];
    for (p, c) in pts.iter_mut().zip(aabb.corners()) {
        let r = c - eye;
        let z = r.dot(forward);
        if !(z > 0.0) {
            return None;
        }
        *p = Vec2::new(r.dot(u), r.dot(v)) / z;
    }
    let hull: ConvexPolygon<8> = convex_hull(&pts);
    Some(hull.area())
}

/// [`projected_area_orthographic`] in closed form, `|d·x|·A_yz + |d·y|·A_xz + |d·z|·A_xy` for unit
/// `d` (each face pair's shadow), for builders that evaluate it many times.
#[must_use]
#[inline]
pub fn projected_area_orthographic_fast(aabb: Aabb, dir: Vec3) -> f32 {
    let e = aabb.extent().max(Vec3::ZERO);
    let d = dir.normalize_or_zero().abs();
    d.x * e.y * e.z + d.y * e.x * e.z + d.z * e.x * e.y
}

/// [`projected_area_perspective`] without a hull: the silhouette of a box seen from outside is
/// tiled by its front faces (those facing the eye, one to three), so the image area is the sum of
/// their projected quads' shoelace areas.
#[must_use]
pub fn projected_area_perspective_fast(aabb: Aabb, eye: Vec3, forward: Vec3) -> Option<f32> {
    let forward = forward.try_normalize()?;
    let (u, v) = plane_basis(forward);
    let corners = aabb.corners();
    let mut image = [Vec2::ZERO; 8];
    for (p, c) in image.iter_mut().zip(corners) {
        let r = c - eye;
        let z = r.dot(forward);
        if !(z > 0.0) {
            return None;
        }
        *p = Vec2::new(r.dot(u), r.dot(v)) / z;
    }
    let mut area = 0.0;
    for axis in 0..3 {
        // The face at max (bit set) faces the eye when the eye is beyond it, and vice versa.
        let side = if eye[axis] > aabb.max[axis] {
            1
        } else if eye[axis] < aabb.min[axis] {
            0
        } else {
            continue;
        };
        let bit = 1 << axis;
        let (a, b) = (1 << ((axis + 1) % 3), 1 << ((axis + 2) % 3));
        let base = if side == 1 { bit } else { 0 };
        let quad = [image[base], image[base | a], image[base | a | b], image[base | b]];
        area += crate::collide::shoelace_area(&quad);
    }
    Some(area)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        let b = Aabb::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(surface_area(b), 22.0);
        assert_eq!(surface_area(Aabb::EMPTY), 0.0);
        assert!((projected_area_orthographic(b, Vec3::Z) - 2.0).abs() < 1e-5);
        // Closed form |d·x|·A_yz + |d·y|·A_xz + |d·z|·A_xy.
        let d = Vec3::new(1.0, 2.0, 2.0) / 3.0;
        let expect = d.x * 6.0 + d.y * 3.0 + d.z * 2.0;
        assert!((projected_area_orthographic(b, d) - expect).abs() < 1e-4);
        // A unit square face at distance 2 straight ahead: image area 1/4.
        let sq = Aabb::new(Vec3::new(-0.5, -0.5, 2.0), Vec3::new(0.5, 0.5, 2.0));
        assert!((projected_area_perspective(sq, Vec3::ZERO, Vec3::Z).unwrap() - 0.25).abs() < 1e-5);
        assert_eq!(projected_area_perspective(b, Vec3::splat(0.5), Vec3::Z), None);
    }

    #[test]
    fn fast_forms_equal_the_hull_forms() {
        let b = Aabb::new(Vec3::new(-0.3, 0.2, 1.0), Vec3::new(0.9, 1.4, 2.5));
        for d in [Vec3::X, Vec3::new(0.3, -0.5, 0.8), Vec3::new(-1.0, 2.0, 0.1)] {
            assert!((projected_area_orthographic(b, d) - projected_area_orthographic_fast(b, d)).abs() < 1e-5);
        }
        for eye in [Vec3::new(0.2, 0.5, -3.0), Vec3::new(4.0, 3.0, -2.0), Vec3::new(0.3, 5.0, 1.5)] {
            let f = b.center() - eye;
            let hull = projected_area_perspective(b, eye, f).unwrap();
            let fast = projected_area_perspective_fast(b, eye, f).unwrap();
            assert!((hull - fast).abs() < 1e-5 * hull.max(1.0), "{hull} vs {fast}");
        }
    }
}
