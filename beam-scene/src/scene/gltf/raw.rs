//! The raw JSON of a glTF file made into the `gltf` crate's typed document, after what that crate
//! cannot type or keep is dealt with: required extensions checked ([`extensions::check`]);
//! animations removed and counted (beam renders one pose, and the crate refuses a channel whose
//! target has no `node`, which the schema allows); a scene without `nodes` given none; each node's
//! `EXT_mesh_gpu_instancing` attributes kept, and each normal texture's `KHR_texture_transform`
//! (the crate reads that extension on other textures only). A document that does not fit the
//! schema's types is an error naming the first element that does not (`nodes[3]: invalid type: …`).

use super::errors::{error, file_error};
use super::extensions;
use crate::error::SceneError;
use crate::read::clip;
use gltf::json::extensions::texture::TextureTransform;
use gltf::json::{self, Value};
use serde::Deserialize;
use serde::de::DeserializeOwned;
use std::collections::HashMap;
use std::path::Path;

/// The accessors of a node's `EXT_mesh_gpu_instancing` attributes (each optional).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Instancing {
    /// Accessor of VEC3 float translations.
    pub translation: Option<usize>,
    /// Accessor of VEC4 rotation quaternions (x, y, z, w; floats or normalized integers).
    pub rotation: Option<usize>,
    /// Accessor of VEC3 float scales.
    pub scale: Option<usize>,
}

/// What was taken from the raw JSON.
#[derive(Debug, Default)]
pub(super) struct Raw {
    /// Animations removed (none is played).
    pub animations: usize,
    /// Node index → its instancing attributes.
    pub instancing: HashMap<usize, Instancing>,
    /// Material index → its normal texture's `KHR_texture_transform`.
    pub normal_transforms: HashMap<usize, TextureTransform>,
}

/// Check and adjust the raw document `root` in place (see the module), and take from it what the
/// typed document does not keep.
pub(super) fn prepare(path: &Path, root: &mut Value) -> Result<Raw, SceneError> {
    extensions::check(path, root)?;
    let mut raw = Raw::default();
    let Some(object) = root.as_object_mut() else {
        return Ok(raw);
    };
    if let Some(animations) = object.remove("animations") {
        raw.animations = animations.as_array().map_or(1, Vec::len);
    }
    if let Some(scenes) = object.get_mut("scenes").and_then(Value::as_array_mut) {
        for scene in scenes.iter_mut().filter_map(Value::as_object_mut) {
            scene.entry("nodes").or_insert_with(|| Value::Array(Vec::new()));
        }
    }
    for (i, node) in extensions::array(root, "nodes").iter().enumerate() {
        let attributes = node.get("extensions").and_then(|e| e.get("EXT_mesh_gpu_instancing"));
        let Some(attributes) = attributes.and_then(|e| e.get("attributes")) else {
            continue;
        };
        let accessor = |name: &str| -> Result<Option<usize>, SceneError> {
            let Some(v) = attributes.get(name) else {
                return Ok(None);
            };
            match v.as_u64().and_then(|k| usize::try_from(k).ok()) {
                Some(k) => Ok(Some(k)),
                None => Err(error(
                    path,
                    format!("nodes[{i}].extensions.EXT_mesh_gpu_instancing.attributes.{name}"),
                    "not an accessor index",
                )),
            }
        };
        let instancing = Instancing {
            translation: accessor("TRANSLATION")?,
            rotation: accessor("ROTATION")?,
            scale: accessor("SCALE")?,
        };
        raw.instancing.insert(i, instancing);
    }
    for (i, material) in extensions::array(root, "materials").iter().enumerate() {
        let at = ["normalTexture", "extensions", "KHR_texture_transform"];
        let Some(v) = at.iter().try_fold(material, |v, key| v.get(key)) else { continue };
        let transform = TextureTransform::deserialize(v)
            .map_err(|e| error(path, format!("materials[{i}].{}", at.join(".")), clip(&e.to_string(), 200)))?;
        raw.normal_transforms.insert(i, transform);
    }
    Ok(raw)
}

/// The typed document of the prepared `root`. On an error, `json` (the file's JSON text) is read
/// again to name the first element that does not fit its type.
pub(super) fn typed(path: &Path, root: Value, json: &[u8]) -> Result<json::Root, SceneError> {
    let e = match json::deserialize::from_value::<json::Root>(root) {
        Ok(root) => return Ok(root),
        Err(e) => e,
    };
    let located = json::deserialize::from_slice::<Value>(json).ok().and_then(|mut root| {
        prepare(path, &mut root).ok()?;
        locate(&root)
    });
    match located {
        Some((at, message)) => Err(error(path, at, clip(&message, 200))),
        None => Err(file_error(path, clip(&e.to_string(), 200))),
    }
}

/// The first element of `root`'s arrays that does not fit its type, and why.
fn locate(root: &Value) -> Option<(String, String)> {
    fn first<T: DeserializeOwned>(root: &Value, key: &str) -> Option<(String, String)> {
        extensions::array(root, key).iter().enumerate().find_map(|(i, item)| {
            let e = T::deserialize(item).err()?;
            Some((format!("{key}[{i}]"), e.to_string()))
        })
    }
    let asset = root.get("asset").and_then(|a| json::Asset::deserialize(a).err());
    asset
        .map(|e| ("asset".to_string(), e.to_string()))
        .or_else(|| first::<json::Accessor>(root, "accessors"))
        .or_else(|| first::<json::buffer::View>(root, "bufferViews"))
        .or_else(|| first::<json::Buffer>(root, "buffers"))
        .or_else(|| first::<json::Camera>(root, "cameras"))
        .or_else(|| first::<json::Image>(root, "images"))
        .or_else(|| first::<json::Material>(root, "materials"))
        .or_else(|| first::<json::Mesh>(root, "meshes"))
        .or_else(|| first::<json::Node>(root, "nodes"))
        .or_else(|| first::<json::texture::Sampler>(root, "samplers"))
        .or_else(|| first::<json::Scene>(root, "scenes"))
        .or_else(|| first::<json::Skin>(root, "skins"))
        .or_else(|| first::<json::Texture>(root, "textures"))
}
