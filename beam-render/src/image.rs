//! Linear RGB images and their files (PNG as sRGB, OpenEXR as linear `f32`; written atomically).

use beam_math::glam::Vec3;
use beam_scene::SceneError;
use std::path::Path;

/// A linear RGB image, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels, `width × height`.
    pub pixels: Vec<Vec3>,
}

/// The sRGB transfer function of a linear value in `[0, 1]`.
#[must_use]
pub fn srgb_encode(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

/// The inverse of [`srgb_encode`].
#[must_use]
pub fn srgb_decode(x: f32) -> f32 {
    if x <= 0.040_45 { x / 12.92 } else { ((x + 0.055) / 1.055).powf(2.4) }
}

impl Image {
    /// A black image.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, pixels: vec![Vec3::ZERO; width as usize * height as usize] }
    }

    /// 8-bit sRGB bytes.
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| p.to_array().map(|c| (srgb_encode(c) * 255.0 + 0.5) as u8)).collect()
    }

    /// Write as PNG (sRGB), atomically.
    pub fn save_png(&self, path: &Path) -> Result<(), SceneError> {
        beam_scene::io::write_png(path, self.width, self.height, &self.to_srgb8())
    }

    /// Write as OpenEXR (linear RGB, 32-bit floats), atomically.
    pub fn save_exr(&self, path: &Path) -> Result<(), SceneError> {
        let whole = beam_scene::region::Placement::whole(self.width, self.height);
        let bytes = beam_scene::io::encode_exr(&self.pixels, whole).map_err(|e| match e {
            SceneError::Image { path: None, message } => SceneError::Image { path: Some(path.into()), message },
            e => e,
        })?;
        beam_scene::io::write_atomic(path, &bytes)
    }

    /// Read an 8-bit PNG (or any format the `image` crate reads) back to linear RGB; a file that
    /// cannot be read or decoded is a [`SceneError::Image`] naming it.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let img = image::open(path)
            .map_err(|e| SceneError::Image { path: Some(path.to_path_buf()), message: e.to_string() })?;
        let img = img.to_rgb8();
        let (width, height) = img.dimensions();
        let pixels = img
            .pixels()
            .map(|p| {
                Vec3::new(
                    srgb_decode(p[0] as f32 / 255.0),
                    srgb_decode(p[1] as f32 / 255.0),
                    srgb_decode(p[2] as f32 / 255.0),
                )
            })
            .collect();
        Ok(Self { width, height, pixels })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trip_and_png() {
        for x in [0.0, 0.001, 0.2, 0.5, 1.0] {
            assert!((srgb_decode(srgb_encode(x)) - x).abs() < 1e-5);
        }
        let dir = tempfile::tempdir().unwrap();
        let mut img = Image::new(3, 2);
        img.pixels[4] = Vec3::new(0.5, 0.25, 1.0);
        let p = dir.path().join("a.png");
        img.save_png(&p).unwrap();
        let back = Image::load(&p).unwrap();
        assert_eq!((back.width, back.height), (3, 2));
        assert!((back.pixels[4] - img.pixels[4]).abs().max_element() < 0.01);
        let e = dir.path().join("a.exr");
        img.pixels[1] = Vec3::new(15.0, 1e-9, 0.1);
        img.save_exr(&e).unwrap();
        let whole = beam_scene::region::Placement::whole(img.width, img.height);
        let pixels = beam_scene::io::read_exr(&e, whole).unwrap();
        assert_eq!(pixels, img.pixels);
    }
}
