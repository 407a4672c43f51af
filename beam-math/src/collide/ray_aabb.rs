//! Ray–AABB intersection by the branchless slab method (004 App. A.1, Alg. A.1).

use crate::shapes::{Aabb, Ray};
use glam::Vec3;

/// Entry and exit parameters of a ray through a box: the `tMin`, `tMax` of 004 Alg. A.1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabHit {
    /// Largest entry parameter over the three slabs.
    pub t_min: f32,
    /// Smallest exit parameter over the three slabs.
    pub t_max: f32,
}

impl SlabHit {
    /// The `collisionDist` of Alg. A.1: `t_min`, or `t_max` when the origin is inside the box.
    #[must_use]
    pub fn distance(self) -> f32 {
        if self.t_min < 0.0 { self.t_max } else { self.t_min }
    }
}

/// Slab test with a precomputed reciprocal direction. Axis-parallel rays need no special case:
/// `1/0 = ±∞` makes the slab bounds `±∞` as IEEE 754 prescribes (004 App. A.1). A ray that lies
/// exactly in a slab plane gives `0·∞ = NaN`; `min`/`max` discard it, which counts the boundary as
/// inside. Returns the hit when `t_max ≥ t_min` and `t_max ≥ 0` (touching counts as a hit).
#[must_use]
#[inline]
pub fn ray_aabb_inv(origin: Vec3, inv_dir: Vec3, aabb: Aabb) -> Option<SlabHit> {
    let t1 = (aabb.min - origin) * inv_dir;
    let t2 = (aabb.max - origin) * inv_dir;
    let t_min = t1.min(t2).max_element();
    let t_max = t1.max(t2).min_element();
    (t_max >= t_min && t_max >= 0.0).then_some(SlabHit { t_min, t_max })
}

/// Ray–AABB slab intersection (004 Alg. A.1). See [`ray_aabb_inv`] for the IEEE details.
#[must_use]
#[inline]
pub fn ray_aabb(ray: Ray, aabb: Aabb) -> Option<SlabHit> {
    ray_aabb_inv(ray.origin, ray.direction.recip(), aabb)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Aabb {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    }

    #[test]
    fn hits_through_the_middle() {
        let h = ray_aabb(Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X), unit()).unwrap();
        assert_eq!((h.t_min, h.t_max), (1.0, 2.0));
        assert_eq!(h.distance(), 1.0);
    }

    #[test]
    fn origin_inside_returns_exit() {
        let h = ray_aabb(Ray::new(Vec3::splat(0.5), Vec3::Y), unit()).unwrap();
        assert_eq!(h.distance(), 0.5);
    }

    #[test]
    fn axis_parallel_rays_use_infinities() {
        // Parallel to x, outside in y: the y slab is (−∞, −∞) → miss.
        assert!(ray_aabb(Ray::new(Vec3::new(-1.0, 2.0, 0.5), Vec3::X), unit()).is_none());
        // Parallel to x, inside in y and z → hit.
        assert!(ray_aabb(Ray::new(Vec3::new(-1.0, 0.25, 0.75), Vec3::X), unit()).is_some());
    }

    #[test]
    fn box_behind_is_missed() {
        assert!(ray_aabb(Ray::new(Vec3::new(2.0, 0.5, 0.5), Vec3::X), unit()).is_none());
    }
}
