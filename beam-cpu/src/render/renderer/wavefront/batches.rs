//! The backend's queries in batches of at most [`MAX_BATCH`], each answer checked to be one per
//! question (a backend that answers otherwise is an error, not a panic); in a scene with cut-outs,
//! its rays' hits checked against their alpha ([`beam_render::cut_outs`]).

use beam_bvh::Hit;
use beam_math::Ray;
use beam_render::BackendError;
use beam_render::cut_outs::{blocked_there, closest_there};
use beam_render::queries::{BeamQueries, LightPolygon, LightQuery, LightSeen};
use beam_scene::scene::Scene;

/// Most rays, segments or shadow-beam queries in one call to the backend.
pub(super) const MAX_BATCH: usize = 1 << 20;

/// The closest hit of each of `rays` on a surface that is there.
pub(super) fn closest_hits(
    backend: &dyn BeamQueries,
    scene: &Scene,
    rays: &[Ray],
) -> Result<Vec<Option<Hit>>, BackendError> {
    closest_there(scene, rays, |rays| nearest(backend, scene, rays))
}

/// Whether each of `segments` is blocked by a surface that is there: where the backend says one
/// is and the scene has cut-outs, its nearest hits are checked.
pub(super) fn any_hits(
    backend: &dyn BeamQueries,
    scene: &Scene,
    segments: &[(Ray, f32)],
) -> Result<Vec<bool>, BackendError> {
    let blocked = in_batches(segments, "segments", |b| backend.any_hits(scene, b))?;
    blocked_there(scene, segments, blocked, |rays| nearest(backend, scene, rays))
}

/// The backend's nearest hit of each of `rays`, whatever its surface.
fn nearest(backend: &dyn BeamQueries, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
    in_batches(rays, "rays", |b| backend.closest_hits(scene, b))
}

/// The answer to each of `queries` about `lights` (`None`: the backend gave up on it).
pub(super) fn light_visibility(
    backend: &dyn BeamQueries,
    scene: &Scene,
    lights: &[LightPolygon],
    queries: &[LightQuery],
) -> Result<Vec<Option<LightSeen>>, BackendError> {
    in_batches(queries, "shadow beams", |b| backend.light_visibility(scene, lights, b))
}

/// `call`'s answers to `items` (`what` they are), [`MAX_BATCH`] at a time.
fn in_batches<T, R>(
    items: &[T],
    what: &str,
    mut call: impl FnMut(&[T]) -> Result<Vec<R>, BackendError>,
) -> Result<Vec<R>, BackendError> {
    let mut out = Vec::with_capacity(items.len());
    for batch in items.chunks(MAX_BATCH) {
        let answers = call(batch)?;
        if answers.len() != batch.len() {
            let message = format!("{} answers to {} {what}", answers.len(), batch.len());
            return Err(BackendError::new("renderer", message));
        }
        out.extend(answers);
    }
    Ok(out)
}
