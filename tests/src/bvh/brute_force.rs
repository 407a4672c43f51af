//! The reference every BVH answer is checked against: every triangle tested.

use beam_bvh::Hit;
use beam_math::collide::WatertightRay;
use beam_math::{Ray, Triangle};

/// Closest hit by testing every triangle (the reference).
#[must_use]
pub fn brute_force_closest(triangles: &[Triangle], ray: Ray, t_max: f32) -> Option<Hit> {
    let wt = WatertightRay::new(ray);
    let mut best: Option<Hit> = None;
    let mut t_best = t_max;
    for (i, t) in triangles.iter().enumerate() {
        if let Some(h) = wt.intersect(t, 0.0, t_best) {
            t_best = h.t;
            best = Some(Hit { prim: i as u32, t: h.t, u: h.u, v: h.v });
        }
    }
    best
}
