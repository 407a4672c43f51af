//! What a loaded scene gets where its file says nothing: the framing camera and the key light of a
//! scene without them, and the check that there is anything to frame at all. The TOML loader
//! ([`super::file`]) and the glTF loader ([`super::gltf`]) both use them.

use super::camera::Camera;
use super::framing;
use super::light::Light;
use crate::error::SceneError;
use beam_math::Triangle;
use std::path::Path;

/// Bounds of the non-degenerate triangles; an error naming the file when there is none.
pub(super) fn valid_bounds(path: &Path, triangles: &[(Triangle, u32)]) -> Result<beam_math::Aabb, SceneError> {
    let bounds = triangles
        .iter()
        .filter(|(t, _)| t.is_valid())
        .fold(beam_math::Aabb::EMPTY, |b, (t, _)| b.grow(t.v[0]).grow(t.v[1]).grow(t.v[2]));
    if bounds.is_valid() { Ok(bounds) } else { Err(SceneError::NoValidTriangle { path: path.to_path_buf() }) }
}

/// The default camera of a scene without one: [`framing::framing_camera`] of what stands in it
/// ([`framing::object_bounds`]).
pub(super) fn default_camera(triangles: &[(Triangle, u32)]) -> Camera {
    framing::framing_camera(objects(triangles))
}

/// The default light of a scene without one: [`framing::key_light`] above and behind `camera`.
pub(super) fn default_light(triangles: &[(Triangle, u32)], camera: &Camera) -> Light {
    framing::key_light(camera, objects(triangles))
}

/// What stands in the scene ([`framing::object_bounds`]).
fn objects(triangles: &[(Triangle, u32)]) -> beam_math::Aabb {
    framing::object_bounds(&triangles.iter().map(|(t, _)| *t).collect::<Vec<_>>())
}
