//! Texture images from their bytes: PNG and JPEG (and for OBJ materials TGA and BMP) decoded by
//! the `image` crate to 8-bit RGBA, bounded in size; every other format refused by name (KTX2,
//! WebP, DDS, …).

use image::ImageFormat;
use std::io::Cursor;
use std::path::Path;
use std::sync::Arc;

/// Image formats a kind of file may use, and their names for a refusal.
pub(crate) struct Formats {
    list: &'static [ImageFormat],
    names: &'static str,
}

/// The formats a glTF image may have (glTF 2.0 §3.8.3).
pub(crate) const GLTF_IMAGES: Formats = Formats { list: &[ImageFormat::Png, ImageFormat::Jpeg], names: "PNG and JPEG" };

/// The formats an OBJ material's map may have: also TGA (common in game assets, known by its
/// extension: a TGA file has no signature) and BMP.
pub(crate) const MTL_IMAGES: Formats = Formats {
    list: &[ImageFormat::Png, ImageFormat::Jpeg, ImageFormat::Tga, ImageFormat::Bmp],
    names: "PNG, JPEG, TGA and BMP",
};

/// Widest and tallest image read, texels.
const MAX_SIDE: u32 = 16_384;

/// Most bytes an image may decode to (as 8-bit RGBA, 4 bytes a texel).
const MAX_DECODED_BYTES: u64 = 1 << 30;

/// A decoded image: width, height and its texels (shared by the textures that read it).
pub(crate) type Decoded = (u32, u32, Arc<[[u8; 4]]>);

/// The image `bytes` (of the file `name`, or an empty name) decoded to 8-bit RGBA, or why not:
/// its format, from its signature or else its name's extension, must be one of `formats`.
pub(crate) fn decode_image(bytes: Vec<u8>, name: &str, formats: &Formats) -> Result<Decoded, String> {
    let accepted = |f: &ImageFormat| formats.list.contains(f);
    let by_name = || Path::new(name).extension().and_then(ImageFormat::from_extension);
    let Some(format) = image::guess_format(&bytes).ok().filter(accepted).or_else(|| by_name().filter(accepted)) else {
        return Err(format!("{} images are not read (only {})", format_name(&bytes), formats.names));
    };
    let mut reader = image::ImageReader::with_format(Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    limits.max_alloc = Some(MAX_DECODED_BYTES);
    reader.limits(limits);
    let rgba = reader.decode().map_err(|e| format!("{format:?} image: {e}"))?.into_rgba8();
    let (width, height) = rgba.dimensions();
    if width == 0 || height == 0 {
        return Err("the image has no texels".into());
    }
    let texels: Arc<[[u8; 4]]> = rgba.pixels().map(|p| p.0).collect();
    Ok((width, height, texels))
}

/// The name of the image format `bytes` start with, for a refusal.
fn format_name(bytes: &[u8]) -> &'static str {
    if bytes.starts_with(b"\xABKTX 20\xBB") {
        "KTX2"
    } else if bytes.len() >= 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        "WebP"
    } else if bytes.starts_with(b"DDS ") {
        "DDS"
    } else {
        match image::guess_format(bytes) {
            Ok(f) => f.extensions_str().first().copied().unwrap_or("these"),
            Err(_) => "unrecognised",
        }
    }
}
