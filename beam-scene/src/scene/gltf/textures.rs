//! The textures a glTF document's materials read: each image decoded once
//! ([`decode_image`]: PNG and JPEG, bounded in size), paired with its sampler (glTF 2.0 §3.8.4).

use super::buffers::{data_uri, file_name, has_scheme};
use super::errors::error;
use crate::error::SceneError;
use crate::read::{MAX_MESH_BYTES, read_bounded, resolve_inside};
use crate::scene::image_file::{Decoded, GLTF_IMAGES, decode_image};
use crate::scene::load_options::LoadOptions;
use crate::scene::surface::{MaterialMaps, TextureRef};
use crate::scene::texture::{Filter, Texture, Wrap};
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

/// The textures `maps` read, decoded, in the order of their first use; the maps' texture indices
/// (glTF texture indices on entry) are rewritten to index the returned list. A normal texture whose
/// image is refused (its format, its size) is dropped from its map instead, and counted (the second
/// value): the model still loads, its shading normals unbent.
pub(super) fn load(
    path: &Path,
    document: &gltf::Document,
    buffers: &[Rc<Vec<u8>>],
    options: &LoadOptions,
    maps: &mut [MaterialMaps],
) -> Result<(Vec<Texture>, usize), SceneError> {
    let mut loader =
        Loader { path, document, buffers, options, textures: Vec::new(), slot: HashMap::new(), images: HashMap::new() };
    let mut dropped = 0;
    for map in maps.iter_mut() {
        let alpha = map.alpha.as_mut().and_then(|a| a.texture.as_mut());
        for t in [map.base_color.as_mut(), map.emissive.as_mut(), alpha].into_iter().flatten() {
            loader.resolve(t)?;
        }
        if let Some(normal) = &mut map.normal
            && loader.resolve(&mut normal.texture).is_err()
        {
            map.normal = None;
            dropped += 1;
        }
    }
    Ok((loader.textures, dropped))
}

/// The textures decoded so far, by glTF texture and by image.
struct Loader<'a> {
    path: &'a Path,
    document: &'a gltf::Document,
    buffers: &'a [Rc<Vec<u8>>],
    options: &'a LoadOptions,
    textures: Vec<Texture>,
    /// Index in `textures` of each glTF texture decoded.
    slot: HashMap<u32, u32>,
    images: HashMap<usize, Decoded>,
}

impl Loader<'_> {
    /// Point `t` (a glTF texture index) at its texture in `textures`, decoding it on first use.
    fn resolve(&mut self, t: &mut TextureRef) -> Result<(), SceneError> {
        if let Some(&i) = self.slot.get(&t.texture) {
            t.texture = i;
            return Ok(());
        }
        let element = format!("texture {}", t.texture);
        let Some(texture) = self.document.textures().nth(t.texture as usize) else {
            return Err(error(self.path, element, "index out of range"));
        };
        let image = texture.source().index();
        let (width, height, texels) = match self.images.get(&image) {
            Some(decoded) => decoded.clone(),
            None => {
                let decoded = decode(self.path, self.document, image, self.buffers, self.options)?;
                self.images.insert(image, decoded.clone());
                decoded
            }
        };
        let sampler = texture.sampler();
        let wrap = |mode| match mode {
            gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
            gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
            gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        };
        let filter = match sampler.mag_filter() {
            Some(gltf::texture::MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Linear,
        };
        let index = self.textures.len() as u32;
        self.textures.push(Texture {
            width,
            height,
            texels,
            wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
            filter,
        });
        self.slot.insert(t.texture, index);
        t.texture = index;
        Ok(())
    }
}

/// Image `index` of `document` decoded to 8-bit RGBA: from its buffer view or its URI (a `data:`
/// URI or a file beside the model).
fn decode(
    path: &Path,
    document: &gltf::Document,
    index: usize,
    buffers: &[Rc<Vec<u8>>],
    options: &LoadOptions,
) -> Result<Decoded, SceneError> {
    let element = format!("image {index}");
    let fail = |m: String| error(path, &element, m);
    let json = &document.as_json().images[index];
    let bytes: Vec<u8> = match (&json.buffer_view, &json.uri) {
        (Some(view), _) => {
            let view = document.views().nth(view.value()).ok_or_else(|| fail("bufferView out of range".into()))?;
            let buffer = &buffers[view.buffer().index()];
            let end = view.offset().checked_add(view.length()).filter(|&e| e <= buffer.len());
            let end = end.ok_or_else(|| fail("its bufferView lies outside its buffer".into()))?;
            buffer[view.offset()..end].to_vec()
        }
        (None, Some(uri)) if has_scheme(uri, "data") => data_uri(uri).map_err(fail)?,
        (None, Some(uri)) => {
            let name = file_name(uri).map_err(fail)?;
            let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let inside = |e: SceneError| SceneError::InMesh {
                path: path.to_path_buf(),
                element: element.clone(),
                source: Box::new(e),
            };
            let (file, _) = resolve_inside(dir, &name, options.allow_outside_paths).map_err(inside)?;
            read_bounded(&file, MAX_MESH_BYTES).map_err(inside)?
        }
        (None, None) => return Err(fail("has neither a bufferView nor a uri".into())),
    };
    decode_image(bytes, "", &GLTF_IMAGES).map_err(fail)
}
