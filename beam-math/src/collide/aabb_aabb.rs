//! AABB–AABB overlap (004 App. A.4).

use crate::shapes::Aabb;

/// True when the boxes overlap on all three axes (touching counts) (004 App. A.4).
#[must_use]
#[inline]
pub fn aabb_aabb(a: Aabb, b: Aabb) -> bool {
    a.min.cmple(b.max).all() && a.max.cmpge(b.min).all()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn hand_worked() {
        let a = Aabb::new(Vec3::ZERO, Vec3::ONE);
        assert!(aabb_aabb(a, Aabb::new(Vec3::splat(0.5), Vec3::splat(2.0))));
        assert!(aabb_aabb(a, Aabb::new(Vec3::ONE, Vec3::splat(2.0))));
        assert!(!aabb_aabb(a, Aabb::new(Vec3::new(1.1, 0.0, 0.0), Vec3::splat(2.0))));
    }
}
