//! glTF 2.0 scenes (`.gltf` JSON or `.glb` binary): the default scene's meshes with their node
//! transforms, the first perspective camera, `KHR_lights_punctual` lights, emissive triangles as
//! area lights and the materials mapped to ours ([`materials`]).
//!
//! The file is read once and bounded; its buffers are the GLB binary chunk, `data:` URIs, or files
//! beside the model resolved like a TOML scene's mesh paths ([`buffers`]). Accessors are read by
//! [`accessor`] with every byte range and index checked; the node hierarchy is walked by [`walk`].
//! Errors name the file and the element (`model.gltf: mesh 2 primitive 0: index 9 out of range
//! (8 vertices)`); nothing in a file can make the loader panic or loop.

mod accessor;
mod buffers;
mod materials;
mod primitive;
mod walk;

use super::file::{LoadOptions, default_camera, default_light, valid_bounds};
use super::{Camera, Scene};
use crate::error::SceneError;
use crate::read::{MAX_MESH_BYTES, clip, read_bounded, visible};
use std::fmt::Display;
use std::path::Path;

/// Most triangles a glTF scene may expand to once meshes are instanced by their nodes (a small
/// file may place a large mesh many times): 2²⁵, about 1.3 GiB of placed triangles before the
/// BVH, so that a few kilobytes of JSON cannot take the machine's memory before `beam render`'s
/// memory estimate is made. Sixty times the Sponza atrium.
const MAX_GLTF_TRIANGLES: usize = 1 << 25;

/// An error of the glTF file `path` at `element` (`mesh 2 primitive 0`, `node 3`).
fn error(path: &Path, element: impl Display, message: impl Display) -> SceneError {
    SceneError::Gltf { path: path.to_path_buf(), element: Some(element.to_string()), message: message.to_string() }
}

/// An error of the glTF file `path` as a whole.
fn file_error(path: &Path, message: impl Display) -> SceneError {
    SceneError::Gltf { path: path.to_path_buf(), element: None, message: message.to_string() }
}

/// Load the glTF 2.0 file `path` (`.gltf` or `.glb`) into a scene: with `options` saying whether
/// its external buffers may lie outside its folder. Without a camera it gets the framing camera
/// of a bare OBJ file; without any light (punctual or emissive), the same light above it.
pub(super) fn load_gltf(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let data = read_bounded(path, MAX_MESH_BYTES)?;
    // A UTF-8 byte-order mark before the JSON is skipped (glTF asks writers for none).
    let json_or_glb = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&data);
    let gltf::Gltf { document, blob } = parse(path, json_or_glb)?;
    drop(data);
    let buffers = buffers::load(path, &document, blob, options)?;
    let materials = materials::map_all(path, &document)?;
    let walked = walk::walk(path, &document, &buffers, &materials)?;
    let bounds = valid_bounds(path, &walked.triangles)?;
    let mut lights = walked.lights;
    if lights.is_empty() {
        lights.push(default_light(bounds));
    }
    let camera: Camera = walked.camera.unwrap_or_else(|| default_camera(bounds));
    let mut scene = Scene::new(path.display().to_string(), walked.triangles, materials, lights, camera);
    scene.stats.skipped_elements = walked.skipped_primitives;
    scene.stats.skipped_lights = walked.skipped_lights;
    scene.notice("point and line primitive(s) skipped: they have no area to render", walked.skipped_primitives);
    scene.notice("directional light(s) skipped: there is no light at infinity here", walked.skipped_lights);
    Ok(scene)
}

/// The document and GLB binary chunk of the file's bytes `data`, validated ([`validate`]). A GLB
/// header is checked here first: its length must cover the header and lie within the file.
fn parse(path: &Path, data: &[u8]) -> Result<gltf::Gltf, SceneError> {
    if data.starts_with(b"glTF") {
        let length = data.get(8..12).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
        match length {
            None => return Err(error(path, "GLB header", "truncated (fewer than 12 bytes)")),
            Some(n) if n < 20 => return Err(error(path, "GLB header", format!("length {n} is too small"))),
            Some(n) if n > data.len() => {
                return Err(error(path, "GLB header", format!("length {n}, but the file has {} bytes", data.len())));
            }
            Some(_) => {}
        }
    }
    let gltf = gltf::Gltf::from_slice_without_validation(data).map_err(|e| match e {
        gltf::Error::Deserialize(e) => {
            let message = e.to_string();
            let message = message.split(" at line ").next().unwrap_or_default();
            let what = if data.starts_with(b"glTF") { "JSON chunk line" } else { "line" };
            error(path, format!("{what} {} column {}", e.line(), e.column()), visible(&clip(message, 200)))
        }
        gltf::Error::Binary(e) => error(path, "GLB container", e),
        other => file_error(path, other),
    })?;
    validate(path, gltf.document.as_json())?;
    Ok(gltf)
}

/// The `gltf` crate's validation of `root` (every index between objects in range, enumerations
/// known, required extensions supported, POSITION accessors with `min` and `max` as the
/// specification demands), after the one check its own validation assumes: each primitive's
/// POSITION accessor exists.
fn validate(path: &Path, root: &gltf::json::Root) -> Result<(), SceneError> {
    use gltf::json::validation::{Checked, Validate};
    let position = Checked::Valid(gltf::Semantic::Positions);
    for (i, mesh) in root.meshes.iter().enumerate() {
        for (j, p) in mesh.primitives.iter().enumerate() {
            if p.attributes.get(&position).is_some_and(|a| a.value() >= root.accessors.len()) {
                let at = format!("meshes[{i}].primitives[{j}].attributes[\"POSITION\"]");
                return Err(error(path, at, "index out of bounds"));
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |at, e| errors.push((at(), e)));
    let Some((at, e)) = errors.first() else {
        return Ok(());
    };
    let more = match errors.len() {
        1 => String::new(),
        n => format!(" (and {} more)", n - 1),
    };
    let message = e.to_string().to_lowercase();
    Err(error(path, visible(&clip(&at.to_string(), 200)), format!("{message}{more}")))
}
