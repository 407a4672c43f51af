//! PNG files that know their place in a frame: a render farm's tile carries a tEXt chunk
//! `beam:region` = `x0,y0,x1,y1,W,H,R` (its pixels `[x0, x1) × [y0, y1)` of a `W × H` frame, of the
//! render R: [`Placement::render`]) before its pixel data. A whole image is written without it,
//! byte for byte as [`encode_png`] writes it, and a PNG without it is a whole frame.

use super::input::{image_error, regular_file};
use crate::error::SceneError;
use crate::region::Placement;
use std::io::BufReader;
use std::path::Path;

/// Keyword of the tEXt chunk that places a tile in its frame.
pub const REGION_KEY: &str = "beam:region";

/// Encode an 8-bit RGB image as PNG bytes.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, SceneError> {
    png_bytes(width, height, rgb).map_err(|source| SceneError::Png { path: None, source })
}

/// The PNG encoding of an 8-bit RGB image.
pub(super) fn png_bytes(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, image::ImageError> {
    let mut bytes = Vec::new();
    let encoder = image::codecs::png::PngEncoder::new(&mut bytes);
    image::ImageEncoder::write_image(encoder, rgb, width, height, image::ExtendedColorType::Rgb8)?;
    Ok(bytes)
}

/// 8-bit RGB `rgb` (the rectangle of `placement`, row-major) as PNG bytes, with its placement when
/// it is not the whole frame.
pub fn encode_png_placed(rgb: &[u8], placement: Placement) -> Result<Vec<u8>, SceneError> {
    let (w, h) = (placement.rect.width(), placement.rect.height());
    if placement.is_whole() {
        return encode_png(w, h, rgb);
    }
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let fail = |e: png::EncodingError| SceneError::Image { path: None, message: e.to_string() };
    encoder.add_text_chunk(REGION_KEY.into(), placement.to_text()).map_err(fail)?;
    let mut writer = encoder.write_header().map_err(fail)?;
    writer.write_image_data(rgb).map_err(fail)?;
    writer.finish().map_err(fail)?;
    Ok(bytes)
}

/// A PNG file's reader past its header, after refusing what is not a regular file.
fn open(path: &Path, limit: usize) -> Result<png::Reader<BufReader<std::fs::File>>, SceneError> {
    let file = regular_file(path)?;
    let decoder = png::Decoder::new_with_limits(BufReader::new(file), png::Limits { bytes: limit });
    decoder.read_info().map_err(|e| image_error(path, e))
}

/// Where the pixels of the PNG file `path` sit: its `beam:region` chunk, else the whole frame of its
/// size. Reads the header only. Errors name the file: a chunk that does not parse, or whose
/// rectangle is not the image's size.
pub fn read_png_placement(path: &Path) -> Result<Placement, SceneError> {
    placement(path, open(path, 1 << 20)?.info())
}

/// The placement that the header `info` of the PNG file `path` gives (see [`read_png_placement`]).
fn placement(path: &Path, info: &png::Info<'_>) -> Result<Placement, SceneError> {
    let fail = |e: &str| image_error(path, e);
    let chunk = info.uncompressed_latin1_text.iter().find(|t| t.keyword == REGION_KEY);
    let Some(chunk) = chunk else { return Ok(Placement::whole(info.width, info.height)) };
    let text: String = chunk.text.chars().take(100).collect();
    let placement = Placement::parse(&chunk.text).ok_or_else(|| {
        fail(&format!(
            "its {REGION_KEY} chunk `{}` is not x0,y0,x1,y1,W,H[,R] of a rectangle in the frame",
            text.escape_debug()
        ))
    })?;
    let (w, h) = (placement.rect.width(), placement.rect.height());
    if (w, h) != (info.width, info.height) {
        return Err(fail(&format!(
            "its {REGION_KEY} chunk `{text}` is {w}×{h}, the image {}×{}",
            info.width, info.height
        )));
    }
    Ok(placement)
}

/// The 8-bit RGB pixels of the PNG file `path` (row-major), which must sit at `expected` (as
/// [`read_png_placement`] found it). Decoding allocates no more than the pixels of `expected`
/// (and the decoder's own 1 MiB), whatever the file says by then. Only 8-bit RGB files (what
/// `beam render` writes) are read. Errors name the file.
pub fn read_png_placed(path: &Path, expected: Placement) -> Result<Vec<u8>, SceneError> {
    let fail = |e: &dyn std::fmt::Display| image_error(path, e);
    let size = expected.rect.len() * 3;
    let mut reader = open(path, size + (1 << 20))?;
    if placement(path, reader.info())? != expected {
        return Err(fail(&"is no longer placed where it was (did the file change?)"));
    }
    let (color, depth) = reader.output_color_type();
    if (color, depth) != (png::ColorType::Rgb, png::BitDepth::Eight) {
        return Err(fail(&format!("is {color:?} {depth:?}; expected 8-bit RGB, as beam render writes")));
    }
    if reader.output_buffer_size() != Some(size) {
        return Err(fail(&"its pixel data does not fill the image"));
    }
    let mut rgb = vec![0; size];
    let frame = reader.next_frame(&mut rgb).map_err(|e| fail(&e))?;
    if frame.buffer_size() != size {
        return Err(fail(&"its pixel data does not fill the image"));
    }
    Ok(rgb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::region::PixelRect;

    #[test]
    fn tiles_keep_their_place_and_whole_images_their_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let rect = PixelRect { x0: 2, y0: 1, x1: 5, y1: 3 };
        let rgb: Vec<u8> = (0..rect.len() * 3).map(|i| i as u8).collect();
        let tile = Placement::new(rect, 6, 4).unwrap();
        let p = dir.path().join("t.png");
        std::fs::write(&p, encode_png_placed(&rgb, tile).unwrap()).unwrap();
        assert_eq!(read_png_placement(&p).unwrap(), tile);
        assert_eq!(read_png_placed(&p, tile).unwrap(), rgb);
        // Readable by any decoder.
        assert_eq!(image::open(&p).unwrap().to_rgb8().into_raw(), rgb);
        let whole = Placement::whole(3, 2);
        assert_eq!(encode_png_placed(&rgb, whole).unwrap(), encode_png(3, 2, &rgb).unwrap());
        std::fs::write(&p, encode_png(3, 2, &rgb).unwrap()).unwrap();
        assert_eq!(read_png_placement(&p).unwrap(), whole);
        let e = read_png_placed(&p, tile).unwrap_err().to_string();
        assert!(e.contains("t.png") && e.contains("no longer placed"), "a file placed elsewhere is refused: {e}");
        // A chunk that lies about the size, or does not parse.
        for (text, says) in [("0,0,4,2,6,4", "is 4×2, the image 3×2"), ("0,0,4", "is not x0,y0,x1,y1,W,H")] {
            let mut bytes = Vec::new();
            let mut encoder = png::Encoder::new(&mut bytes, 3, 2);
            encoder.set_color(png::ColorType::Rgb);
            encoder.add_text_chunk(REGION_KEY.into(), text.into()).unwrap();
            encoder.write_header().unwrap().write_image_data(&rgb).unwrap();
            std::fs::write(&p, bytes).unwrap();
            let e = read_png_placement(&p).unwrap_err().to_string();
            assert!(e.contains("t.png") && e.contains(says), "{e}");
        }
    }
}
