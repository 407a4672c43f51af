//! Frustum–AABB intersection: the AABB rejection test followed by the separating-axis test over
//! the 26 candidate axes of 004 App. A.5 (Alg. A.3).

use super::aabb_aabb::aabb_aabb;
use super::frustum::Frustum;
use crate::shapes::Aabb;
use glam::Vec3;

/// The candidate separating axes of 004 App. A.5: 3 box normals, the frustum face normals (5
/// distinct for a camera frustum) and the cross products of the 3 box edge directions with the
/// frustum edge directions (6 for a camera frustum): 26 in all for a rectangular frustum.
#[must_use]
pub fn separating_axes(frustum: &Frustum) -> ([Vec3; 40], usize) {
    let mut axes = [Vec3::ZERO; 40];
    let mut n = 0;
    let mut push = |a: Vec3| {
        if a.length_squared() > 1e-20 {
            axes[n] = a;
            n += 1;
        }
    };
    for a in [Vec3::X, Vec3::Y, Vec3::Z] {
        push(a);
    }
    // The far face is parallel to the near one: skip it (5 distinct face normals).
    for (i, p) in frustum.planes().iter().enumerate() {
        if i != 1 {
            push(p.normal);
        }
    }
    let (edges, ne) = frustum.edge_directions();
    for b in [Vec3::X, Vec3::Y, Vec3::Z] {
        for e in &edges[..ne] {
            push(b.cross(*e));
        }
    }
    (axes, n)
}

/// Projection interval of a box on an axis. The extreme corners are chosen from the axis signs
/// without projecting all eight (the table of 004 App. A.5.1).
#[inline]
fn box_interval(aabb: Aabb, axis: Vec3) -> (f32, f32) {
    let lo = Vec3::select(axis.cmpge(Vec3::ZERO), aabb.min, aabb.max);
    let hi = Vec3::select(axis.cmpge(Vec3::ZERO), aabb.max, aabb.min);
    (lo.dot(axis), hi.dot(axis))
}

#[inline]
fn frustum_interval(frustum: &Frustum, axis: Vec3) -> (f32, f32) {
    frustum.near.iter().chain(frustum.far.iter()).fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
        let d = p.dot(axis);
        (lo.min(d), hi.max(d))
    })
}

/// True when the frustum and the box overlap (touching counts): the rejection test against the
/// frustum's own box, then no separating axis among [`separating_axes`] (004 Alg. A.3).
#[must_use]
pub fn frustum_aabb(frustum: &Frustum, aabb: Aabb) -> bool {
    if !aabb_aabb(frustum.aabb(), aabb) {
        return false;
    }
    let (axes, n) = separating_axes(frustum);
    axes[..n].iter().all(|&axis| {
        let (a_min, a_max) = box_interval(aabb, axis);
        let (b_min, b_max) = frustum_interval(frustum, axis);
        b_min <= a_max && b_max >= a_min
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn camera() -> Frustum {
        let view = Mat4::look_at_rh(Vec3::ZERO, -Vec3::Z, Vec3::Y);
        let proj = Mat4::perspective_rh(1.0, 1.0, 0.5, 10.0);
        Frustum::from_view_projection(proj * view)
    }

    #[test]
    fn camera_frustum_has_26_axes() {
        // A camera in general orientation: 3 + 5 + 3·6 axes, none degenerate.
        let view = Mat4::look_at_rh(Vec3::new(1.0, 2.0, 3.0), Vec3::new(-0.3, 0.2, -1.0), Vec3::new(0.1, 1.0, 0.2));
        let f = Frustum::from_view_projection(Mat4::perspective_rh(1.0, 1.3, 0.5, 10.0) * view);
        assert_eq!(separating_axes(&f).1, 26);
        // Axis-aligned, two box-edge × frustum-edge products vanish and are skipped.
        assert_eq!(separating_axes(&camera()).1, 24);
    }

    #[test]
    fn hand_worked() {
        let f = camera();
        assert!(frustum_aabb(&f, Aabb::new(Vec3::new(-0.5, -0.5, -3.0), Vec3::new(0.5, 0.5, -2.0))));
        assert!(!frustum_aabb(&f, Aabb::new(Vec3::new(-0.5, -0.5, 1.0), Vec3::new(0.5, 0.5, 2.0))));
        assert!(!frustum_aabb(&f, Aabb::new(Vec3::new(-0.5, -0.5, -30.0), Vec3::new(0.5, 0.5, -20.0))));
    }

    #[test]
    fn sat_rejects_what_the_box_test_accepts() {
        // A box in the corner outside a side plane but inside the frustum's bounding box.
        let f = camera();
        let b = Aabb::new(Vec3::new(5.0, 5.0, -2.0), Vec3::new(5.5, 5.5, -1.5));
        assert!(aabb_aabb(f.aabb(), b));
        assert!(!frustum_aabb(&f, b));
    }
}
