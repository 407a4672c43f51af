//! AABB against a set of half-spaces: the plane test of frustum culling.

use crate::shapes::Aabb;
use glam::Vec3;

/// True when the box lies wholly outside one of the half-spaces `n·x ≤ d`: tested at the box corner
/// nearest to the inside of each plane. Conservative: a box outside the intersection of the
/// half-spaces but inside each one is not rejected (only the separating-axis test of
/// [`super::frustum_aabb`] decides those).
#[must_use]
#[inline]
pub fn aabb_outside_planes(bounds: &Aabb, planes: &[(Vec3, f32)]) -> bool {
    planes.iter().any(|&(n, d)| n.dot(Vec3::select(n.cmpgt(Vec3::ZERO), bounds.min, bounds.max)) > d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        assert!(aabb_outside_planes(&b, &[(Vec3::X, -0.5)]));
        assert!(!aabb_outside_planes(&b, &[(Vec3::X, 0.5)]));
        assert!(!aabb_outside_planes(&b, &[(-Vec3::X, 0.0), (Vec3::Y, 2.0)]));
    }
}
