//! Seeds of an eye beam: the triangles that a grid of rays sees split it first, nearest first, so
//! that big near occluders own the beam before the BVH's order of boxes matters.

use beam_bvh::FlatBvh;
use beam_math::Triangle;
use beam_math::glam::Vec2;
use beam_math::polybeam::BeamFrame;

/// Rays per side of the grid whose hits seed a beam ([`seen_by_rays`]): the grid that predicts
/// the beam's cost, which the renderer casts for both.
const SEED_RAYS: u32 = crate::render::eye_budget::GRID;

/// The distinct triangles that rays through a grid of points of the window `[lo, hi]` hit, nearest
/// first.
pub(super) fn seen_by_rays(bvh: &FlatBvh, triangles: &[Triangle], frame: &BeamFrame, lo: Vec2, hi: Vec2) -> Vec<u32> {
    let mut hits: Vec<(f32, u32)> = Vec::with_capacity((SEED_RAYS * SEED_RAYS) as usize);
    for j in 0..SEED_RAYS {
        for i in 0..SEED_RAYS {
            let f = (Vec2::new(i as f32, j as f32) + 0.5) / SEED_RAYS as f32;
            let ray = frame.ray(lo + f * (hi - lo));
            if let Some(hit) = bvh.closest_hit(triangles, ray, f32::INFINITY) {
                hits.push((hit.t, hit.prim));
            }
        }
    }
    nearest_first(hits)
}

/// The distinct triangles of `hits` (`(t, prim)` of rays from the apex, `t` in units of the
/// distance to the image plane), nearest first.
pub(crate) fn nearest_first(mut hits: Vec<(f32, u32)>) -> Vec<u32> {
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut seeds: Vec<u32> = Vec::with_capacity(hits.len());
    for (_, p) in hits {
        if !seeds.contains(&p) {
            seeds.push(p);
        }
    }
    seeds
}
