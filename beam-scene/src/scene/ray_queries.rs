//! A scene's own ray queries, through its cut-outs: the nearest surface a ray meets and whether a
//! segment is blocked, where a triangle of a cut-out material ([`AlphaCut`]) is there only where
//! its coverage says so. Scenes without cut-outs query the 8-wide BVH once; with them, a ray that
//! meets a cut-out triangle where it is not there goes on from that hit, at most [`MAX_LAYERS`]
//! times.

use super::Scene;
use super::surface::AlphaCut;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;

/// Most cut-out layers a ray passes through; past them it stops at the next (a bound on a query's
/// work in a forest of leaves).
const MAX_LAYERS: u32 = 64;

impl Scene {
    /// Whether some triangle's material is a cut-out (taken when the scene was assembled).
    #[must_use]
    pub fn has_cut_outs(&self) -> bool {
        self.cut_outs
    }

    /// The cut-out of triangle `prim`'s material, if it has one.
    #[must_use]
    pub fn cut_out(&self, prim: u32) -> Option<AlphaCut> {
        if !self.cut_outs {
            return None;
        }
        self.surfaces.cut_out(self.material_of[prim as usize])
    }

    /// The nearest hit of `ray` below `t_max` on a surface that is there.
    #[must_use]
    pub fn closest_hit(&self, ray: Ray, t_max: f32) -> Option<Hit> {
        if !self.cut_outs {
            return self.wide.closest_hit(ray, t_max);
        }
        let key = ray_key(&ray);
        let mut from = 0.0f32;
        for _ in 0..MAX_LAYERS {
            let mut hit = self.wide.closest_hit(Ray::new(ray.at(from), ray.direction), t_max - from)?;
            hit.t += from;
            if self.stops(&hit, key) {
                return Some(hit);
            }
            // On from just past the hit (relative to its distance, so that the same triangle is
            // not met again at t ≈ 0).
            from = hit.t + hit.t.abs().max(f32::MIN_POSITIVE) * 1e-5;
        }
        self.wide.closest_hit(Ray::new(ray.at(from), ray.direction), t_max - from).map(|mut h| {
            h.t += from;
            h
        })
    }

    /// Whether `ray` meets a surface that is there below `t_max` (a shadow ray or segment).
    #[must_use]
    pub fn occluded(&self, ray: Ray, t_max: f32) -> bool {
        // Nothing at all in the way is the common case, and the cheapest query.
        self.wide.any_hit(ray, t_max) && (!self.cut_outs || self.closest_hit(ray, t_max).is_some())
    }

    /// Whether the surface `hit` is on is there for the ray of hash `key`.
    fn stops(&self, hit: &Hit, key: u32) -> bool {
        match self.cut_out(hit.prim) {
            None => true,
            Some(cut) => {
                let w = Vec3::new(1.0 - hit.u - hit.v, hit.u, hit.v);
                self.surfaces.stops(cut, hit.prim, w, key)
            }
        }
    }
}

/// A hash of a ray's origin and direction (their bits, mixed), the key of `BLEND` cut-outs: rays
/// that differ see independent coverage.
fn ray_key(ray: &Ray) -> u32 {
    let bits = [ray.origin, ray.direction].map(|v| v.to_array().map(f32::to_bits));
    let mut h = 0x9e37_79b9u32;
    for b in bits.iter().flatten() {
        h = (h ^ b).wrapping_mul(0x85eb_ca6b);
        h ^= h >> 13;
    }
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^ (h >> 16)
}
