//! A scene file's `[environment]` table, checked into an [`Environment`]: `color = [r, g, b]` (a
//! uniform sky) or `map = "sky.hdr"` (an equirectangular `.hdr` or `.exr` map, named relative to
//! the scene file's folder and kept inside it as meshes are), with an optional `intensity` that
//! scales either and a `rotation` about +Y (degrees) for a map.

use super::check::colour;
use super::environment::{Environment, EnvironmentMap};
use super::format::EnvironmentFile;
use crate::error::SceneError;
use crate::read::resolve_inside;
use beam_math::glam::Vec3;
use std::path::Path;
use std::sync::Arc;

/// The environment of the scene file `path` (in folder `dir`) that `e` describes; its map read
/// (`allow_outside`: the map may lie outside `dir`). Errors name the file and the key
/// (`environment.map`), and for the map its own file too.
pub(super) fn environment(
    path: &Path,
    dir: &Path,
    allow_outside: bool,
    e: &EnvironmentFile,
) -> Result<Environment, SceneError> {
    let invalid = |message: &str| SceneError::Invalid {
        path: path.to_path_buf(),
        element: "environment".into(),
        message: message.into(),
    };
    let out_of_range = |key: &str, expected| SceneError::OutOfRange {
        path: path.to_path_buf(),
        element: format!("environment.{key}"),
        expected,
    };
    let intensity = e.intensity.unwrap_or(1.0);
    if !(intensity >= 0.0 && intensity.is_finite()) {
        return Err(out_of_range("intensity", "a finite number ≥ 0"));
    }
    match (&e.color, &e.map) {
        (Some(_), Some(_)) => Err(invalid("give color or map, not both")),
        (None, None) => Err(invalid("needs color = [r, g, b] or map = \"sky.hdr\" (or .exr)")),
        (Some(c), None) => {
            if e.rotation.is_some() {
                return Err(invalid("rotation applies to a map, not a color"));
            }
            colour(path, "environment.color", *c)?;
            Ok(Environment::Constant(Vec3::from_array(*c) * intensity))
        }
        (None, Some(name)) => {
            let rotation = e.rotation.unwrap_or(0.0);
            if !rotation.is_finite() {
                return Err(out_of_range("rotation", "a finite angle in degrees"));
            }
            let in_scene = |e| SceneError::InMesh {
                path: path.to_path_buf(),
                element: "environment.map".into(),
                source: Box::new(e),
            };
            let (file, _) = resolve_inside(dir, name, allow_outside).map_err(in_scene)?;
            let map = EnvironmentMap::load(&file).map_err(in_scene)?;
            Ok(Environment::Map(Arc::new(map.with_intensity(intensity).with_rotation(rotation))))
        }
    }
}
