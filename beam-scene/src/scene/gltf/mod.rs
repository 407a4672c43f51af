//! glTF 2.0 scenes (`.gltf` JSON or `.glb` binary): the default scene's meshes with their node
//! transforms (and `EXT_mesh_gpu_instancing` instances), the first camera ([`camera`]; an
//! orthographic one approximated), `KHR_lights_punctual` lights, emissive triangles as area lights
//! and the materials mapped to ours ([`materials`]), morph targets under their default weights.
//! Skins and animations are not applied: one pose is drawn, and each is noticed. `docs/gltf.md` lists what is read.
//!
//! Required extensions we do not read are refused by name first ([`extensions`]); the raw JSON is
//! then typed ([`raw`]). The file is read once and bounded; its buffers are the GLB binary chunk, `data:` URIs, or files
//! beside the model resolved like a TOML scene's mesh paths ([`buffers`]). Accessors are read by
//! [`accessor`] with every byte range and index checked; the node hierarchy is walked by [`walk`].
//! Errors name the file and the element (`model.gltf: mesh 2 primitive 0: index 9 out of range
//! (8 vertices)`); nothing in a file can make the loader panic or loop.

mod accessor;
mod buffers;
mod camera;
mod errors;
mod extensions;
mod instancing;
mod materials;
mod primitive;
mod raw;
mod sparse;
mod textures;
mod view;
mod walk;

use super::camera::Camera;
use super::defaults::{default_camera, default_light, valid_bounds};
use super::environment::Environment;
use super::interior;
use super::load_options::LoadOptions;
use super::model::Scene;
use super::surface::{MaterialMaps, Surfaces};
use crate::error::SceneError;
use crate::read::{MAX_MESH_BYTES, clip, read_bounded, visible};
use errors::{error, file_error};
use std::path::Path;

/// Load the glTF 2.0 file `path` (`.gltf` or `.glb`) into a scene: with `options` saying whether
/// its external buffers may lie outside its folder. Without a camera it gets the framing camera
/// of a bare OBJ file; without any light (punctual or emissive), the same light above it.
pub(super) fn load_gltf(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let data = read_bounded(path, MAX_MESH_BYTES)?;
    // A UTF-8 byte-order mark before the JSON is skipped (glTF asks writers for none).
    let json_or_glb = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&data);
    let (gltf::Gltf { document, blob }, raw) = parse(path, json_or_glb)?;
    drop(data);
    let buffers = buffers::load(path, &document, blob, options)?;
    let (materials, mut maps) = materials::map_all(path, &document, &raw.normal_transforms)?;
    let emissive_maps = maps.iter().filter(|m| m.emissive.is_some()).count();
    let (textures, unread_normal_maps) = textures::load(path, &document, &buffers, options, &mut maps)?;
    if maps.iter().all(MaterialMaps::is_empty) {
        maps.clear();
    }
    let surfaces = Surfaces { textures, maps, ..Surfaces::default() };
    let walked = walk::walk(path, &document, &buffers, &materials, &raw.instancing, surfaces)?;
    valid_bounds(path, &walked.triangles)?;
    let framed = walked.camera.is_none();
    let camera: Camera = walked.camera.unwrap_or_else(|| default_camera(&walked.triangles));
    let mut lights = walked.lights;
    // A model without a light of its own is shown under a neutral sky with a key light.
    let without_lights = lights.is_empty();
    if without_lights {
        lights.push(default_light(&walked.triangles, &camera));
    }
    let name = path.display().to_string();
    let mut scene = Scene::with_surfaces(name, walked.triangles, materials, lights, camera, walked.surfaces);
    if without_lights {
        scene.environment = Environment::neutral_sky();
    }
    if framed {
        interior::look_inside(&mut scene, without_lights);
    }
    scene.stats.skipped_elements = walked.skipped_primitives;
    scene.stats.skipped_lights = walked.skipped_lights;
    scene.notice("point and line primitive(s) skipped: they have no area to render", walked.skipped_primitives);
    scene.notice("directional light(s) skipped: there is no light at infinity here", walked.skipped_lights);
    let orthographic = usize::from(walked.orthographic);
    scene.notice("orthographic camera(s) approximated by a distant narrow perspective camera", orthographic);
    scene.notice("spot light(s) drawn as point lights: their cone is not kept", walked.spot_lights);
    scene.notice("skin(s) ignored: meshes are drawn in their bind pose", walked.skins);
    scene.notice("animation(s) ignored: beam renders one pose", raw.animations);
    let count = |f: fn(&gltf::Material) -> bool| document.materials().filter(f).count();
    let cut_outs = count(|m| m.alpha_mode() != gltf::material::AlphaMode::Opaque);
    let opaque = cut_outs - scene.surfaces.maps.iter().filter(|m| m.alpha.is_some()).count();
    let unread = "normal texture(s) not read (their image is refused): shading uses the triangles' own normals";
    scene.notice(unread, unread_normal_maps);
    scene.notice("mirror, glass and emissive material(s) with alphaMode MASK or BLEND drawn opaque", opaque);
    let unlit = count(|m| m.unlit());
    scene.notice("unlit material(s) (KHR_materials_unlit) drawn as diffuse: lit by the scene", unlit);
    scene.notice(
        "emissive texture(s) lighting the scene by their mean over each triangle (seen texel by texel)",
        emissive_maps,
    );
    Ok(scene)
}

/// The document and GLB binary chunk of the file's bytes `data`, validated ([`validate`]), and
/// what was taken from its raw JSON before it was typed ([`raw`]). A GLB header is checked here
/// first: its length must cover the header and lie within the file.
fn parse(path: &Path, data: &[u8]) -> Result<(gltf::Gltf, raw::Raw), SceneError> {
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
    let (json, blob) = if data.starts_with(b"glTF") {
        let glb = gltf::Glb::from_slice(data).map_err(|e| match e {
            gltf::Error::Binary(e) => error(path, "GLB container", e),
            other => file_error(path, other),
        })?;
        (glb.json, glb.bin.map(|b| b.into_owned()))
    } else {
        (std::borrow::Cow::Borrowed(data), None)
    };
    let mut value: gltf::json::Value = gltf::json::deserialize::from_slice(&json).map_err(|e| {
        let message = e.to_string();
        let message = message.split(" at line ").next().unwrap_or_default();
        let what = if data.starts_with(b"glTF") { "JSON chunk line" } else { "line" };
        error(path, format!("{what} {} column {}", e.line(), e.column()), visible(&clip(message, 200)))
    })?;
    let raw = raw::prepare(path, &mut value)?;
    let root = raw::typed(path, value, &json)?;
    validate(path, &root)?;
    Ok((gltf::Gltf { document: gltf::Document::from_json_without_validation(root), blob }, raw))
}

/// The `gltf` crate's validation of `root` (every index between objects in range, enumerations
/// known, POSITION accessors with `min` and `max` as the specification demands), after the one
/// check its own validation assumes: each primitive's POSITION accessor exists. Two of its
/// findings are not errors here: a required extension it does not know (the required ones were
/// checked by [`extensions::check`]), and an accessor without a buffer view (valid: its elements
/// are zeros, [`accessor`]).
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
    root.validate(root, gltf::json::Path::new, &mut |at, e| {
        let at = at();
        let zeros = at.as_str().starts_with("accessors[") && at.as_str().ends_with("].bufferView");
        if !(at.as_str().starts_with("extensionsRequired") || zeros && e == gltf::json::validation::Error::Missing) {
            errors.push((at, e));
        }
    });
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
