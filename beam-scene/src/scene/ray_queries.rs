//! A scene's own ray queries, through its cut-outs: the nearest surface a ray meets and whether a
//! segment is blocked, where a triangle of a cut-out material ([`AlphaCut`]) is there only where
//! its coverage says so. Scenes without cut-outs query the 8-wide BVH once; with them, a ray that
//! meets a cut-out triangle where it is not there goes on from that hit, at most [`MAX_CUT_OUT_LAYERS`]
//! times. Eye rays may blend `BLEND` surfaces instead ([`Scene::blended_hits`]).

use super::cut_out_triangles::CutOutTriangles;
use super::model::Scene;
use super::surface::AlphaCut;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;

/// Most cut-out layers a ray passes through; past them it stops at the next (a bound on a query's
/// work in a forest of leaves).
pub const MAX_CUT_OUT_LAYERS: u32 = 64;

impl Scene {
    /// Whether some triangle's material is a cut-out (taken when the scene was assembled).
    #[must_use]
    pub fn has_cut_outs(&self) -> bool {
        self.cut_outs.is_some()
    }

    /// The cut-out triangles and their BVH, when there are any.
    #[must_use]
    pub fn cut_out_triangles(&self) -> Option<&CutOutTriangles> {
        self.cut_outs.as_ref()
    }

    /// The cut-out of triangle `prim`'s material, if it has one.
    #[must_use]
    pub fn cut_out(&self, prim: u32) -> Option<AlphaCut> {
        self.cut_outs.as_ref()?;
        self.surfaces.cut_out(self.material_of[prim as usize])
    }

    /// The nearest hit of `ray` below `t_max` on a surface that is there.
    #[must_use]
    pub fn closest_hit(&self, ray: Ray, t_max: f32) -> Option<Hit> {
        if self.cut_outs.is_none() {
            return self.wide.closest_hit(ray, t_max);
        }
        let key = ray_key(&ray);
        let mut from = 0.0;
        for _ in 0..MAX_CUT_OUT_LAYERS {
            let hit = self.hit_from(ray, from, t_max)?;
            if self.there(key, &hit) {
                return Some(hit);
            }
            from = past_hit(&hit);
        }
        self.hit_from(ray, from, t_max)
    }

    /// Whether the surface `hit` is on is there for `ray`, as [`Scene::closest_hit`] decides at
    /// each layer: always off cut-outs, where α reaches the cutoff on a `MASK`, with probability α
    /// on a `BLEND` (by the hash of the ray and the triangle). For hits a caller found itself: a
    /// nonlinear beam's texel ray against one triangle (000 Alg. 1), which goes on to the next
    /// nearest where the surface is not there, as a rasterizer's alpha test discards a fragment.
    #[must_use]
    pub fn is_there(&self, ray: &Ray, hit: &Hit) -> bool {
        self.cut_out(hit.prim).is_none() || self.there(ray_key(ray), hit)
    }

    /// [`Scene::is_there`] for a ray of hash `key`: a draw of its own for each surface, so that
    /// layers pass independently.
    fn there(&self, key: u32, hit: &Hit) -> bool {
        let alpha = self.coverage(hit);
        alpha >= 1.0 || alpha > unit(mix(key ^ hit.prim.wrapping_mul(0x9e37_79b9)))
    }

    /// The nearest hit of `ray` between `from` and `t_max` on a surface that a `MASK` leaves there,
    /// and its coverage there: α of a `BLEND` surface, 1 of any other (a `BLEND` surface is there
    /// for a ray with probability α: [`Scene::closest_hit`] decides by a hash of the ray; an eye
    /// ray may instead blend α of it with `1 − α` of what lies behind).
    #[must_use]
    pub fn nearest_surface(&self, ray: Ray, mut from: f32, t_max: f32) -> Option<(Hit, f32)> {
        for _ in 0..MAX_CUT_OUT_LAYERS {
            let hit = self.hit_from(ray, from, t_max)?;
            let alpha = self.coverage(&hit);
            if alpha > 0.0 {
                return Some((hit, alpha));
            }
            from = past_hit(&hit);
        }
        self.hit_from(ray, from, t_max).map(|h| (h, 1.0))
    }

    /// How much of the surface `hit` is on is there: 1 off cut-outs, 0 or 1 on a `MASK` (its
    /// cutoff decides), α in `[0, 1]` on a `BLEND`.
    fn coverage(&self, hit: &Hit) -> f32 {
        let Some(cut) = self.cut_out(hit.prim) else { return 1.0 };
        let alpha = self.surfaces.alpha(cut, hit.prim, Vec3::new(1.0 - hit.u - hit.v, hit.u, hit.v));
        match cut.cutoff {
            Some(cutoff) => f32::from(alpha >= cutoff),
            None => alpha.clamp(0.0, 1.0),
        }
    }

    /// What an eye ray sees through `BLEND` surfaces, blended as a rasterizer blends them (front to
    /// back, without noise): calls `seen(hit, share)` for each surface `ray` meets below `t_max`, in
    /// order, up to the first that is wholly there; `share` is its part of the ray's radiance, its
    /// coverage times what the surfaces in front of it let through. Returns what they all let
    /// through (the environment's share; 0 when an opaque surface ends the ray).
    pub fn blended_hits(&self, ray: Ray, t_max: f32, mut seen: impl FnMut(Hit, f32)) -> f32 {
        let (mut through, mut from) = (1.0f32, 0.0);
        for _ in 0..MAX_CUT_OUT_LAYERS {
            let Some((hit, alpha)) = self.nearest_surface(ray, from, t_max) else { return through };
            seen(hit, through * alpha);
            through *= 1.0 - alpha;
            if through <= 0.0 {
                return 0.0;
            }
            from = past_hit(&hit);
        }
        // Past the most layers, the next surface takes what is left (as `closest_hit` stops there).
        match self.hit_from(ray, from, t_max) {
            Some(hit) => {
                seen(hit, through);
                0.0
            }
            None => through,
        }
    }

    /// Whether `ray` meets a surface that is there below `t_max` (a shadow ray or segment).
    #[must_use]
    pub fn occluded(&self, ray: Ray, t_max: f32) -> bool {
        // Nothing at all in the way is the common case, and the cheapest query.
        self.wide.any_hit(ray, t_max) && (self.cut_outs.is_none() || self.closest_hit(ray, t_max).is_some())
    }

    /// [`Scene::occluded`], with the same answer, first testing the triangles (a block of four of
    /// the BVH's leaves) that stopped the last ray asked about through `last`, which this updates
    /// ([`Bvh8::occluding_block`]). With cut-outs, it is [`Scene::occluded`].
    ///
    /// [`Bvh8::occluding_block`]: beam_bvh::Bvh8::occluding_block
    #[must_use]
    pub fn occluded_after(&self, ray: Ray, t_max: f32, last: &mut Option<u32>) -> bool {
        if self.cut_outs.is_some() {
            return self.occluded(ray, t_max);
        }
        let block = self.wide.occluding_block(ray, t_max, *last);
        *last = block.or(*last);
        block.is_some()
    }

    /// The nearest hit of `ray` between `from` and `t_max`, whatever its surface.
    fn hit_from(&self, ray: Ray, from: f32, t_max: f32) -> Option<Hit> {
        let mut hit = self.wide.closest_hit(Ray::new(ray.at(from), ray.direction), t_max - from)?;
        hit.t += from;
        Some(hit)
    }
}

/// Where a ray goes on from past `hit`: just beyond it, relative to its distance, so that the same
/// triangle is not met again at `t ≈ 0`.
pub fn past_hit(hit: &Hit) -> f32 {
    hit.t + hit.t.abs().max(f32::MIN_POSITIVE) * 1e-5
}

/// A hash of a ray's origin and direction (their bits, mixed), the key of `BLEND` cut-outs: rays
/// that differ see independent coverage.
fn ray_key(ray: &Ray) -> u32 {
    let bits = [ray.origin, ray.direction].map(|v| v.to_array().map(f32::to_bits));
    bits.iter().flatten().fold(0x9e37_79b9u32, |h, &b| mix(h ^ b))
}

/// A 32-bit mixing step (multiply, xor-shift: the finalizer of MurmurHash3).
fn mix(mut h: u32) -> u32 {
    h = (h ^ (h >> 16)).wrapping_mul(0x85eb_ca6b);
    h = (h ^ (h >> 13)).wrapping_mul(0xc2b2_ae35);
    h ^ (h >> 16)
}

/// `h` as a number in `[0, 1)`: its top 24 bits over 2²⁴ (exact in an `f32`, never 1).
fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}
