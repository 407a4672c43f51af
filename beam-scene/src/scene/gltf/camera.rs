//! A glTF camera as ours (a pinhole). An orthographic camera is approximated by a perspective one
//! far behind it along its view direction, with a narrow field of view ([`ORTHOGRAPHIC_FOV`])
//! that covers the same `ymag` half-height at the orthographic camera's position: rays at most
//! 1° from parallel, and what lies `ymag` beyond that plane drawn about 2 % smaller.

use super::errors::error;
use crate::error::SceneError;
use crate::scene::camera::Camera;
use beam_math::glam::{Mat4, Vec3};
use gltf::json::camera::Type;
use gltf::json::validation::Checked;
use std::path::Path;

/// Vertical field of view, in degrees, of the perspective camera standing for an orthographic one.
const ORTHOGRAPHIC_FOV: f32 = 2.0;

/// Image height of a glTF camera, in pixels (its width follows its aspect ratio).
const HEIGHT: u32 = 512;

/// Our camera for glTF camera `index` placed by `world` (it looks down its local −z with +y up),
/// and whether it approximates an orthographic one: a perspective camera's vertical field of view
/// from `yfov`; [`HEIGHT`] pixels high and as wide as its aspect ratio says (`aspectRatio`, or
/// `xmag / ymag`; square without one). `None` when the camera does not exist or its type has no
/// projection of that type.
pub(super) fn camera(
    path: &Path,
    document: &gltf::Document,
    index: usize,
    world: Mat4,
) -> Result<Option<(Camera, bool)>, SceneError> {
    let element = format!("camera {index}");
    let Some(json) = document.as_json().cameras.get(index) else {
        return Ok(None);
    };
    let (fov_y, aspect, back) = match (&json.type_, &json.perspective, &json.orthographic) {
        (Checked::Valid(Type::Perspective), Some(p), _) => {
            let fov_y = p.yfov.to_degrees();
            if !(fov_y > 0.0 && fov_y < 180.0) {
                return Err(error(path, element, format!("yfov {} must lie between 0 and π", p.yfov)));
            }
            (fov_y, p.aspect_ratio.unwrap_or(1.0), None)
        }
        (Checked::Valid(Type::Orthographic), _, Some(o)) => {
            let (x, y) = (o.xmag.abs(), o.ymag.abs());
            if !(x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()) {
                return Err(error(
                    path,
                    element,
                    format!("xmag {} and ymag {} must be non-zero numbers", o.xmag, o.ymag),
                ));
            }
            let back = y / (ORTHOGRAPHIC_FOV / 2.0).to_radians().tan();
            (ORTHOGRAPHIC_FOV, x / y, Some(back))
        }
        _ => return Ok(None),
    };
    if !(aspect > 0.0 && aspect.is_finite()) {
        return Err(error(path, element, format!("aspectRatio {aspect} must be a positive number")));
    }
    let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let up = world.transform_vector3(Vec3::Y);
    if forward == Vec3::ZERO || !(up.cross(forward).length_squared() > 0.0) {
        return Err(error(path, element, "its node's transform collapses the view direction or up vector"));
    }
    let position = world.transform_point3(Vec3::ZERO) - forward * back.unwrap_or(0.0);
    if !position.is_finite() {
        return Err(error(path, element, "its position overflows (values must stay finite)"));
    }
    let width = (HEIGHT as f32 * aspect).round().clamp(1.0, 4096.0) as u32;
    let camera = Camera { position, target: position + forward, up, fov_y, width, height: HEIGHT };
    Ok(Some((camera, back.is_some())))
}
