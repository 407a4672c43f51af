//! Which glTF extensions a file may require: those we read load; any other in `extensionsRequired`
//! is refused by name before anything else of the file is checked, so that a Draco or meshopt file
//! is not reported as "accessors[0].bufferView: missing data". A compressed primitive or buffer
//! that is used without its extension being required, and without the uncompressed fallback the
//! extension then demands, is refused by name too.

use super::errors::error;
use crate::error::SceneError;
use crate::read::{QUOTE_CHARS, clip};
use gltf::json::Value;
use std::path::Path;

/// Extensions read (or approximated, see `docs/gltf.md`), so a file may require them.
pub(super) const SUPPORTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_unlit",
    "KHR_texture_transform",
    // Integer and normalized attributes are read by the accessor reader.
    "KHR_mesh_quantization",
    "EXT_mesh_gpu_instancing",
];

/// What the extensions most often required, and not read, are (for the message).
const KNOWN: &[(&str, &str)] = &[
    ("KHR_draco_mesh_compression", "Draco mesh compression"),
    ("EXT_meshopt_compression", "meshopt compression"),
    ("KHR_meshopt_compression", "meshopt compression"),
    ("KHR_texture_basisu", "KTX2 / Basis Universal textures"),
    ("EXT_texture_webp", "WebP textures"),
    ("EXT_texture_avif", "AVIF textures"),
    ("MSFT_texture_dds", "DDS textures"),
    ("KHR_materials_pbrSpecularGlossiness", "specular-glossiness materials"),
];

/// `name` with what it is when known: `KHR_draco_mesh_compression (Draco mesh compression)`.
fn described(name: &str) -> String {
    let name_shown = clip(&name.escape_debug().to_string(), QUOTE_CHARS);
    match KNOWN.iter().find(|(n, _)| *n == name) {
        Some((_, what)) => format!("{name_shown} ({what})"),
        None => name_shown,
    }
}

/// Refuse the raw document `root` when its `extensionsRequired` names an extension we do not
/// read (all of them are named), or when it uses Draco or meshopt compression without the
/// uncompressed fallback.
pub(super) fn check(path: &Path, root: &Value) -> Result<(), SceneError> {
    let required = root.get("extensionsRequired").and_then(Value::as_array);
    let refused: Vec<String> = required
        .into_iter()
        .flatten()
        .filter_map(Value::as_str)
        .filter(|name| !SUPPORTED.contains(name))
        .map(described)
        .collect();
    match refused.len() {
        0 => {}
        1 => return Err(error(path, "extensionsRequired", format!("{} is not supported", refused[0]))),
        _ => return Err(error(path, "extensionsRequired", format!("{} are not supported", refused.join(", ")))),
    }
    check_fallbacks(path, root)
}

/// Refuse a Draco-compressed primitive whose POSITION accessor has no buffer view (no uncompressed
/// fallback), and a buffer that is only a meshopt fallback (it has no data of its own).
fn check_fallbacks(path: &Path, root: &Value) -> Result<(), SceneError> {
    let accessors = array(root, "accessors");
    for (i, mesh) in array(root, "meshes").iter().enumerate() {
        for (j, p) in array(mesh, "primitives").iter().enumerate() {
            if p.get("extensions").and_then(|e| e.get("KHR_draco_mesh_compression")).is_none() {
                continue;
            }
            let position = p.get("attributes").and_then(|a| a.get("POSITION")).and_then(Value::as_u64);
            let accessor = position.and_then(|k| accessors.get(usize::try_from(k).ok()?));
            if accessor.is_some_and(|a| a.get("bufferView").is_none()) {
                return Err(error(
                    path,
                    format!("meshes[{i}].primitives[{j}]"),
                    format!(
                        "{} is not supported, and the primitive has no uncompressed data",
                        described("KHR_draco_mesh_compression")
                    ),
                ));
            }
        }
    }
    for (i, buffer) in array(root, "buffers").iter().enumerate() {
        for name in ["EXT_meshopt_compression", "KHR_meshopt_compression"] {
            let ext = buffer.get("extensions").and_then(|e| e.get(name));
            if ext.and_then(|e| e.get("fallback")).and_then(Value::as_bool) == Some(true) {
                return Err(error(
                    path,
                    format!("buffers[{i}]"),
                    format!("{} is not supported, and this buffer is its fallback, with no data", described(name)),
                ));
            }
        }
    }
    Ok(())
}

/// The array `key` of the object `v`; empty when there is none.
pub(super) fn array<'a>(v: &'a Value, key: &str) -> &'a [Value] {
    v.get(key).and_then(Value::as_array).map_or(&[], Vec::as_slice)
}
