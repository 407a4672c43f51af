//! OpenEXR files of linear RGB: 32-bit float channels R, G, B, ZIP-compressed scan lines, one
//! layer. A render farm's tile is placed the format's own way: its pixels are the data window, its
//! frame the display window (anchored at the origin); a whole image has the two equal.

use super::input::{image_error, regular_file};
use crate::error::SceneError;
use crate::region::{PixelRect, Placement};
use beam_math::glam::Vec3;
use exr::meta::attribute::{AttributeValue, Text};
use exr::prelude::{
    Encoding, Image, IntegerBounds, Layer, LayerAttributes, ReadChannels, ReadLayers, SpecificChannels, Vec2,
    WritableImage,
};
use std::io::{BufReader, Cursor};
use std::path::Path;

/// Name of the header attribute holding [`Placement::render`] in hexadecimal (absent: 0).
pub(super) const RENDER_KEY: &str = "beamRender";

/// `pixels` (row-major, the rectangle of `placement`) as EXR bytes, placed in the frame. Errors for
/// a pixel count that does not match, or a frame too large for the format's 32-bit coordinates.
pub fn encode_exr(pixels: &[Vec3], placement: Placement) -> Result<Vec<u8>, SceneError> {
    let r = placement.rect;
    let (w, h) = (r.width() as usize, r.height() as usize);
    if pixels.len() != w * h {
        return Err(SceneError::Image { path: None, message: format!("{} pixels for a {w}×{h} image", pixels.len()) });
    }
    let fits = |v: u32| i32::try_from(v).is_ok();
    if !(fits(placement.frame_width) && fits(placement.frame_height)) {
        let message = format!("a {}×{} frame is too large for OpenEXR", placement.frame_width, placement.frame_height);
        return Err(SceneError::Image { path: None, message });
    }
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let c = pixels[p.y() * w + p.x()];
        (c.x, c.y, c.z)
    });
    let position = Vec2(r.x0 as i32, r.y0 as i32);
    let layer =
        Layer::new((w, h), LayerAttributes::default().with_position(position), Encoding::SMALL_LOSSLESS, channels);
    let mut image = Image::from_layer(layer);
    let frame = (placement.frame_width as usize, placement.frame_height as usize);
    image.attributes.display_window = IntegerBounds::new((0, 0), frame);
    if placement.render != 0 {
        let render = AttributeValue::Text(Text::from(format!("{:016x}", placement.render).as_str()));
        image.attributes.other.insert(Text::from(RENDER_KEY), render);
    }
    let mut bytes = Cursor::new(Vec::new());
    image
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(|e| SceneError::Image { path: None, message: e.to_string() })?;
    Ok(bytes.into_inner())
}

/// Where the pixels of the EXR file `path` sit: its data window in its display window (a file
/// whose two windows are equal is a whole frame). Reads the header only. Errors name the file.
pub fn read_exr_placement(path: &Path) -> Result<Placement, SceneError> {
    let fail = |e: &dyn std::fmt::Display| image_error(path, e);
    let file = regular_file(path)?;
    let meta = exr::meta::MetaData::read_from_buffered(BufReader::new(file), false).map_err(|e| fail(&e))?;
    let [header] = meta.headers.as_slice() else {
        return Err(fail(&format!("has {} layers; expected one (an image beam writes)", meta.headers.len())));
    };
    let (data, display) = (header.data_window(), header.shared_attributes.display_window);
    let rect = |lo: i64, size: usize| u32::try_from(lo).ok().zip(u32::try_from(lo + size as i64).ok());
    let (dx, dy) = (display.position.x() as i64, display.position.y() as i64);
    let x = rect(data.position.x() as i64 - dx, data.size.width());
    let y = rect(data.position.y() as i64 - dy, data.size.height());
    let (w, h) = (u32::try_from(display.size.width()).ok(), u32::try_from(display.size.height()).ok());
    let placement = match (x, y, w, h) {
        (Some((x0, x1)), Some((y0, y1)), Some(w), Some(h)) => Placement::new(PixelRect { x0, y0, x1, y1 }, w, h),
        _ => None,
    };
    let placement = placement.ok_or_else(|| fail(&"its data window is empty or not inside its display window"))?;
    // Written among the image's attributes; a reader may file an unknown one with the layer's.
    let key = Text::from(RENDER_KEY);
    let found = header.shared_attributes.other.get(&key).or_else(|| header.own_attributes.other.get(&key));
    let render = match found {
        None => 0,
        Some(AttributeValue::Text(t)) => u64::from_str_radix(&t.to_string(), 16)
            .map_err(|_| fail(&format!("its {RENDER_KEY} attribute is not a hexadecimal fingerprint")))?,
        Some(_) => return Err(fail(&format!("its {RENDER_KEY} attribute is not text"))),
    };
    Ok(placement.of_render(render))
}

/// The EXR file `path`'s RGB pixels (row-major, its data window; any sample type, as `f32`),
/// which must sit at `expected` (as [`read_exr_placement`] found it). Decoding allocates at most the
/// pixels of `expected`, whatever the file says by then. Errors name the file (one without R, G
/// and B too, or placed elsewhere).
pub fn read_exr(path: &Path, expected: Placement) -> Result<Vec<Vec3>, SceneError> {
    let fail = |e: &dyn std::fmt::Display| image_error(path, e);
    if read_exr_placement(path)? != expected {
        return Err(fail(&"is no longer placed where it was (did the file change?)"));
    }
    let n = expected.rect.len();
    let file = regular_file(path)?;
    let (width, pixels) = read_rgb(BufReader::new(file), n).map_err(|e| fail(&e))?;
    if pixels.len() != n || width != expected.rect.width() as usize {
        return Err(fail(&"its pixels do not fill its data window"));
    }
    Ok(pixels)
}

/// The R, G and B channels of the first valid layer of the OpenEXR image `reader` (at its largest
/// resolution level): its width and at most `n` pixels, row-major.
pub(crate) fn read_rgb(
    reader: impl std::io::Read + std::io::Seek,
    n: usize,
) -> Result<(usize, Vec<Vec3>), exr::error::Error> {
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| (size.width(), vec![Vec3::ZERO; size.area().min(n)]),
            |(w, px): &mut (usize, Vec<Vec3>), p: Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                if let Some(v) = px.get_mut(p.y() * *w + p.x()) {
                    *v = Vec3::new(r, g, b);
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .from_buffered(reader)?;
    Ok(image.layer_data.channel_data.pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_and_placement_round_trip_bit_for_bit() {
        let dir = tempfile::tempdir().unwrap();
        let rect = PixelRect { x0: 3, y0: 5, x1: 7, y1: 8 };
        let pixels: Vec<Vec3> =
            (0..rect.len()).map(|i| Vec3::new(i as f32 * 0.1, 1e-30 * i as f32, 1234.567 + i as f32)).collect();
        for placement in [Placement::new(rect, 10, 9).unwrap().of_render(0x1234_5678_9abc_def0), Placement::whole(4, 3)]
        {
            let p = dir.path().join("a.exr");
            std::fs::write(&p, encode_exr(&pixels, placement).unwrap()).unwrap();
            assert_eq!(read_exr_placement(&p).unwrap(), placement);
            let back = read_exr(&p, placement).unwrap();
            let bits = |v: &[Vec3]| v.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&back), bits(&pixels));
        }
        assert!(encode_exr(&pixels[1..], Placement::whole(4, 3)).is_err());
        let elsewhere = Placement::new(PixelRect { x0: 0, y0: 0, x1: 4, y1: 3 }, 10, 9).unwrap();
        let e = read_exr(&dir.path().join("a.exr"), elsewhere).unwrap_err().to_string();
        assert!(e.contains("a.exr") && e.contains("no longer placed"), "{e}");
        std::fs::write(dir.path().join("b.exr"), b"not an exr").unwrap();
        assert!(read_exr(&dir.path().join("b.exr"), elsewhere).unwrap_err().to_string().contains("b.exr"));
    }
}
