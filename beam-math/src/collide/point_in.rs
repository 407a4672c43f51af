//! Point containment: in an AABB (004 App. A.6), in a frustum by the homogeneous clip test (A.7),
//! in a convex polygon by the inside–outside test (A.8).

use crate::shapes::Aabb;
use glam::{Mat4, Vec2, Vec3};

/// `min ≤ p ≤ max` component-wise (004 App. A.6).
#[must_use]
#[inline]
pub fn point_in_aabb(p: Vec3, aabb: Aabb) -> bool {
    p.cmpge(aabb.min).all() && p.cmple(aabb.max).all()
}

/// Homogeneous clip test `−w ≤ x ≤ w`, `−w ≤ y ≤ w`, `0 ≤ z ≤ w` of `p' = M·p`, without the
/// perspective division (004 App. A.7; the `[0, 1]` depth range of wgpu and glam, see its footnote).
#[must_use]
#[inline]
pub fn point_in_frustum(view_projection: Mat4, p: Vec3) -> bool {
    let c = view_projection * p.extend(1.0);
    c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && c.z >= 0.0 && c.z <= c.w
}

/// Inside–outside test of a point against a convex polygon of either winding (004 Alg. A.4): the
/// point is inside when every edge cross product has the sign of the reference one. Points on an
/// edge count as outside, as in Alg. A.4 (`≤ 0` rejects).
#[must_use]
pub fn point_in_convex_polygon(p: Vec2, hull: &[Vec2]) -> bool {
    let n = hull.len();
    if n < 3 {
        return false;
    }
    let reference = (hull[0] - hull[n - 1]).perp_dot(p - hull[n - 1]);
    (0..n).all(|i| {
        let cross = (hull[(i + 1) % n] - hull[i]).perp_dot(p - hull[i]);
        reference * cross > 0.0
    })
}

/// The 3D form of Alg. A.4 for a point on the plane of a planar convex polygon: cross products are
/// vectors and "same direction" is a positive dot product.
#[must_use]
pub fn point_in_convex_polygon_3d(p: Vec3, hull: &[Vec3]) -> bool {
    let n = hull.len();
    if n < 3 {
        return false;
    }
    let reference = (hull[0] - hull[n - 1]).cross(p - hull[n - 1]);
    (0..n).all(|i| {
        let cross = (hull[(i + 1) % n] - hull[i]).cross(p - hull[i]);
        reference.dot(cross) > 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aabb_and_polygon() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        assert!(point_in_aabb(Vec3::splat(0.5), b));
        assert!(point_in_aabb(Vec3::ONE, b));
        assert!(!point_in_aabb(Vec3::new(0.5, 1.5, 0.5), b));
        let sq = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        assert!(point_in_convex_polygon(Vec2::splat(0.5), &sq));
        let mut cw = sq;
        cw.reverse();
        assert!(point_in_convex_polygon(Vec2::splat(0.5), &cw));
        assert!(!point_in_convex_polygon(Vec2::new(1.5, 0.5), &sq));
        let sq3 = sq.map(|v| Vec3::new(v.x, 0.0, v.y));
        assert!(point_in_convex_polygon_3d(Vec3::new(0.3, 0.0, 0.6), &sq3));
        assert!(!point_in_convex_polygon_3d(Vec3::new(-0.3, 0.0, 0.6), &sq3));
    }

    #[test]
    fn clip_test() {
        let view = Mat4::look_at_rh(Vec3::ZERO, -Vec3::Z, Vec3::Y);
        let m = Mat4::perspective_rh(1.0, 1.0, 0.5, 10.0) * view;
        assert!(point_in_frustum(m, Vec3::new(0.0, 0.0, -2.0)));
        assert!(!point_in_frustum(m, Vec3::new(0.0, 0.0, 2.0)));
        assert!(!point_in_frustum(m, Vec3::new(0.0, 0.0, -0.25)));
        assert!(!point_in_frustum(m, Vec3::new(0.0, 0.0, -11.0)));
        assert!(!point_in_frustum(m, Vec3::new(3.0, 0.0, -2.0)));
    }
}
