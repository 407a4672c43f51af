//! Ray–plane intersection (004 App. A.2, Alg. A.2).

use crate::shapes::{Plane, Ray};

/// The parameter `t = −(⟨n·O⟩ + D) / ⟨n·d⟩` where the ray meets the plane (004 Alg. A.2).
/// `None` when the ray is parallel to the plane or the point lies behind the origin (`t < 0`).
#[must_use]
#[inline]
pub fn ray_plane(ray: Ray, plane: Plane) -> Option<f32> {
    let nd = plane.normal.dot(ray.direction);
    if nd == 0.0 {
        return None;
    }
    let t = -plane.eval(ray.origin) / nd;
    (t >= 0.0).then_some(t)
}

/// Like [`ray_plane`] but keeps negative `t` (a line–plane intersection); used by transfers.
#[must_use]
#[inline]
pub fn line_plane(ray: Ray, plane: Plane) -> Option<f32> {
    let nd = plane.normal.dot(ray.direction);
    (nd != 0.0).then(|| -plane.eval(ray.origin) / nd)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn hand_worked() {
        let plane = Plane::from_point_normal(Vec3::new(0.0, 0.0, 3.0), Vec3::Z);
        let ray = Ray::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 2.0));
        assert_eq!(ray_plane(ray, plane), Some(1.5));
        assert_eq!(ray_plane(Ray::new(Vec3::ZERO, Vec3::X), plane), None);
        assert_eq!(ray_plane(Ray::new(Vec3::ZERO, -Vec3::Z), plane), None);
        assert_eq!(line_plane(Ray::new(Vec3::ZERO, -Vec3::Z), plane), Some(-3.0));
    }
}
