//! The bytes of a glTF document's buffers: the GLB binary chunk, a `data:` URI decoded (base64 or
//! percent-encoded), or a file beside the model, resolved inside the model's folder with the rule of
//! a TOML scene's mesh paths ([`resolve_inside`]) and read once, bounded.

use super::errors::error;
use crate::error::SceneError;
use crate::read::{MAX_MESH_BYTES, QUOTE_CHARS, clip, read_bounded, resolve_inside};
use crate::scene::load_options::LoadOptions;
use base64::Engine as _;
use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Standard base64, padded or not.
const BASE64: GeneralPurpose = GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
);

/// The bytes of each buffer of `document` (in order), each at least its `byteLength` long. `blob`
/// is the GLB binary chunk; a file named by several buffers is read once.
pub(super) fn load(
    path: &Path,
    document: &gltf::Document,
    blob: Option<Vec<u8>>,
    options: &LoadOptions,
) -> Result<Vec<Rc<Vec<u8>>>, SceneError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let blob = blob.map(Rc::new);
    let mut files: HashMap<PathBuf, Rc<Vec<u8>>> = HashMap::new();
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let element = format!("buffer {}", buffer.index());
        let fail = |message: String| error(path, &element, message);
        // The buffer file's own error (not found, too large, outside the folder), kept whole.
        let inside = |e: SceneError| SceneError::InMesh {
            path: path.to_path_buf(),
            element: element.clone(),
            source: Box::new(e),
        };
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.clone().ok_or_else(|| {
                fail("has no URI, so it is the GLB binary chunk, which this file does not have".into())
            })?,
            gltf::buffer::Source::Uri(uri) if has_scheme(uri, "data") => Rc::new(data_uri(uri).map_err(fail)?),
            gltf::buffer::Source::Uri(uri) => {
                let name = file_name(uri).map_err(&fail)?;
                let (file, _) = resolve_inside(dir, &name, options.allow_outside_paths).map_err(inside)?;
                match files.get(&file) {
                    Some(data) => data.clone(),
                    None => {
                        let data = Rc::new(read_bounded(&file, MAX_MESH_BYTES).map_err(inside)?);
                        files.insert(file, data.clone());
                        data
                    }
                }
            }
        };
        if data.len() < buffer.length() {
            return Err(fail(format!("holds {} bytes, fewer than its byteLength {}", data.len(), buffer.length())));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// Whether `uri` starts with the scheme `scheme:` (in any case).
pub(super) fn has_scheme(uri: &str, scheme: &str) -> bool {
    uri.len() > scheme.len()
        && uri.is_char_boundary(scheme.len())
        && uri[..scheme.len()].eq_ignore_ascii_case(scheme)
        && uri[scheme.len()..].starts_with(':')
}

/// The bytes of a `data:[<media type>][;base64],<data>` URI.
pub(super) fn data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let Some((header, body)) = uri.split_once(',') else {
        return Err("a data: URI without a comma before its data".into());
    };
    if header.to_ascii_lowercase().ends_with(";base64") {
        BASE64.decode(body.trim_end()).map_err(|e| format!("data: URI: not valid base64 ({e})"))
    } else {
        Ok(percent_encoding::percent_decode_str(body).collect())
    }
}

/// The relative file name a buffer URI stands for: percent-decoded; other schemes (`http:`,
/// `file:`) are refused.
pub(super) fn file_name(uri: &str) -> Result<String, String> {
    let scheme = uri.split_once(':').map(|(s, _)| s).filter(|s| {
        let mut c = s.chars();
        c.next().is_some_and(|c| c.is_ascii_alphabetic())
            && c.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
    });
    if let Some(scheme) = scheme {
        return Err(format!(
            "URI scheme `{}:` is not read (only data: URIs and paths relative to the model)",
            clip(&scheme.escape_debug().to_string(), QUOTE_CHARS)
        ));
    }
    percent_encoding::percent_decode_str(uri)
        .decode_utf8()
        .map(|s| s.into_owned())
        .map_err(|_| format!("`{}`: not a UTF-8 file name", clip(&uri.escape_debug().to_string(), QUOTE_CHARS)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uris_and_file_names() {
        assert_eq!(data_uri("data:application/octet-stream;base64,AAEC").unwrap(), [0, 1, 2]);
        assert_eq!(data_uri("data:application/gltf-buffer;base64,AAE").unwrap(), [0, 1]);
        assert_eq!(data_uri("data:,a%20b").unwrap(), b"a b");
        assert!(data_uri("data:;base64,A*==").unwrap_err().contains("base64"));
        assert!(data_uri("data:nothing").is_err());
        assert!(has_scheme("DATA:,x", "data") && !has_scheme("data.bin", "data"));
        assert_eq!(file_name("my%20mesh.bin").unwrap(), "my mesh.bin");
        assert!(file_name("http://example.invalid/a.bin").unwrap_err().contains("`http:`"));
        assert!(file_name("a%FF.bin").unwrap_err().contains("UTF-8"));
    }
}
