//! Rays through cut-outs by a backend that takes every triangle as opaque (a GPU's ray tracer tests
//! no alpha): each hit on a cut-out triangle is checked on the host ([`Scene::is_there`], the
//! decision [`Scene::closest_hit`] makes at each layer) and, where the surface is not there, the
//! ray goes on from just past it ([`past_hit`]) with the backend's next nearest hit, the rays of a
//! layer in one batch, at most [`MAX_CUT_OUT_LAYERS`] layers (the host finishes what is left). A
//! shadow segment the backend says is blocked is checked the same way. A backend that sees through
//! cut-outs itself (the CPU's) returns hits that are there, and nothing changes.

use crate::BackendError;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_scene::scene::{MAX_CUT_OUT_LAYERS, Scene, past_hit};

/// The nearest hit on a surface that is there of each segment `(ray, t_max)`, from the nearest
/// hits, whatever their surface, that `closest` (the backend's, one answer per ray) finds for the
/// segments' rays and for rays sent on from past a cut-out.
pub fn hits_there(
    scene: &Scene,
    segments: &[(Ray, f32)],
    closest: impl Fn(&[Ray]) -> Result<Vec<Option<Hit>>, BackendError>,
) -> Result<Vec<Option<Hit>>, BackendError> {
    let within = |h: Option<Hit>, t_max: f32| h.filter(|h| h.t < t_max);
    let first = closest(&segments.iter().map(|s| s.0).collect::<Vec<_>>())?;
    let mut hits: Vec<Option<Hit>> = first.into_iter().zip(segments).map(|(h, &(_, t_max))| within(h, t_max)).collect();
    let not_there = |i: usize, hits: &[Option<Hit>]| hits[i].is_some_and(|h| !scene.is_there(&segments[i].0, &h));
    let mut pending: Vec<usize> = (0..segments.len()).filter(|&i| not_there(i, &hits)).collect();
    for _ in 0..MAX_CUT_OUT_LAYERS {
        if pending.is_empty() {
            break;
        }
        // Past each cut-out hit, along the same ray (so the hits keep the original ray's `t`).
        let from: Vec<f32> = pending.iter().map(|&i| hits[i].map_or(0.0, |h| past_hit(&h))).collect();
        let rays: Vec<Ray> =
            pending.iter().zip(&from).map(|(&i, &f)| Ray::new(segments[i].0.at(f), segments[i].0.direction)).collect();
        for ((&i, &f), h) in pending.iter().zip(&from).zip(closest(&rays)?) {
            hits[i] = within(h.map(|h| Hit { t: h.t + f, ..h }), segments[i].1);
        }
        pending.retain(|&i| not_there(i, &hits));
    }
    // Past the most layers, the host's own query (as deep as the scene's).
    for i in pending {
        hits[i] = scene.closest_hit(segments[i].0, segments[i].1);
    }
    Ok(hits)
}

/// The nearest hit on a surface that is there of each of `rays`: `closest`'s own hits in a scene
/// without cut-outs, else [`hits_there`] over the whole rays.
pub fn closest_there(
    scene: &Scene,
    rays: &[Ray],
    closest: impl Fn(&[Ray]) -> Result<Vec<Option<Hit>>, BackendError>,
) -> Result<Vec<Option<Hit>>, BackendError> {
    if !scene.has_cut_outs() {
        return closest(rays);
    }
    let segments: Vec<(Ray, f32)> = rays.iter().map(|&r| (r, f32::INFINITY)).collect();
    hits_there(scene, &segments, closest)
}

/// Whether each of `segments` is blocked by a surface that is there, from `blocked`, whether the
/// backend found any triangle on it: in a scene with cut-outs, where it did, [`hits_there`] by
/// `closest` decides.
pub fn blocked_there(
    scene: &Scene,
    segments: &[(Ray, f32)],
    mut blocked: Vec<bool>,
    closest: impl Fn(&[Ray]) -> Result<Vec<Option<Hit>>, BackendError>,
) -> Result<Vec<bool>, BackendError> {
    if !scene.has_cut_outs() {
        return Ok(blocked);
    }
    let suspects: Vec<usize> = (0..segments.len()).filter(|&i| blocked[i]).collect();
    let checked: Vec<(Ray, f32)> = suspects.iter().map(|&i| segments[i]).collect();
    for (i, hit) in suspects.into_iter().zip(hits_there(scene, &checked, closest)?) {
        blocked[i] = hit.is_some();
    }
    Ok(blocked)
}
