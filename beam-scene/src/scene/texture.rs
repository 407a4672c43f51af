//! Textures: an image of 8-bit RGBA texels (colour decoded from sRGB when read) with the sampler of glTF 2.0 §3.8.4 (wrap modes per
//! axis, nearest or bilinear filtering), looked up at texture coordinates `(u, v)` with `v` down
//! the image (glTF's convention: (0, 0) is the top-left corner of the first texel).

use beam_math::glam::{Vec2, Vec4};
use std::sync::{Arc, LazyLock};

/// How a texture coordinate outside [0, 1] maps into the image (glTF `wrapS`, `wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image repeats (`REPEAT`, glTF's default).
    #[default]
    Repeat,
    /// Every other repetition is mirrored (`MIRRORED_REPEAT`).
    MirroredRepeat,
    /// The edge texels extend outwards (`CLAMP_TO_EDGE`).
    ClampToEdge,
}

/// How texels combine at a point (glTF `magFilter`; minification also filters bilinearly, without
/// mipmaps, unless the sampler asks for nearest texels).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// The nearest texel.
    Nearest,
    /// Bilinear interpolation of the four nearest texels.
    #[default]
    Linear,
}

/// An image of 8-bit RGBA texels and its sampler. Colour channels are sRGB-encoded and read as
/// linear values (alpha is linear).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Width in texels (≥ 1).
    pub width: u32,
    /// Height in texels (≥ 1).
    pub height: u32,
    /// Texels, row-major from the top row (`width × height` of them; shared by the textures that
    /// read one image with different samplers).
    pub texels: Arc<[[u8; 4]]>,
    /// Wrap mode along u and along v.
    pub wrap: [Wrap; 2],
    /// Filter.
    pub filter: Filter,
}

impl Texture {
    /// The filtered texel value at texture coordinates `uv` (non-finite coordinates read texel 0),
    /// its colour decoded from sRGB.
    #[must_use]
    pub fn sample(&self, uv: Vec2) -> Vec4 {
        self.filtered(uv, &SRGB)
    }

    /// [`Texture::sample`] of a texture whose channels are data, not colour (a normal map): every
    /// channel read as `code / 255`.
    #[must_use]
    pub fn sample_data(&self, uv: Vec2) -> Vec4 {
        self.filtered(uv, &LINEAR)
    }

    fn filtered(&self, uv: Vec2, table: &[f32; 256]) -> Vec4 {
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        let (x, y) = (uv.x * self.width as f32, uv.y * self.height as f32);
        match self.filter {
            Filter::Nearest => self.texel(x.floor() as i64, y.floor() as i64, table),
            Filter::Linear => {
                // Texel centres lie at half-integers.
                let (x, y) = (x - 0.5, y - 0.5);
                let (x0, y0) = (x.floor(), y.floor());
                let (fx, fy) = (x - x0, y - y0);
                let (x0, y0) = (x0 as i64, y0 as i64);
                let top = self.texel(x0, y0, table).lerp(self.texel(x0 + 1, y0, table), fx);
                let bottom = self.texel(x0, y0 + 1, table).lerp(self.texel(x0 + 1, y0 + 1, table), fx);
                top.lerp(bottom, fy)
            }
        }
    }

    /// Texel `(x, y)` after wrapping each coordinate into the image, its colour channels decoded
    /// by `table`.
    fn texel(&self, x: i64, y: i64, table: &[f32; 256]) -> Vec4 {
        let x = wrap(x, self.width, self.wrap[0]);
        let y = wrap(y, self.height, self.wrap[1]);
        let [r, g, b, a] = self.texels.get(y as usize * self.width as usize + x as usize).copied().unwrap_or([255; 4]);
        Vec4::new(table[r as usize], table[g as usize], table[b as usize], f32::from(a) / 255.0)
    }
}

/// Integer texel coordinate `i` wrapped into `0..n` by `mode`.
fn wrap(i: i64, n: u32, mode: Wrap) -> u32 {
    let n = i64::from(n.max(1));
    (match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let k = i.rem_euclid(2 * n);
            if k < n { k } else { 2 * n - 1 - k }
        }
    }) as u32
}

/// Each 8-bit code as a value in [0, 1].
const LINEAR: [f32; 256] = {
    let mut t = [0.0; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = i as f32 / 255.0;
        i += 1;
    }
    t
};

/// The linear value of each 8-bit sRGB code.
static SRGB: LazyLock<[f32; 256]> = LazyLock::new(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)));

/// Linear value of the sRGB-encoded channel `c` in [0, 1] (IEC 61966-2-1).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_one(filter: Filter, wrap: Wrap) -> Texture {
        Texture { width: 2, height: 1, texels: Arc::new([[0; 4], [255; 4]]), wrap: [wrap; 2], filter }
    }

    #[test]
    fn nearest_reads_the_texel_under_the_point() {
        let t = two_by_one(Filter::Nearest, Wrap::Repeat);
        assert_eq!(t.sample(Vec2::new(0.25, 0.5)), Vec4::ZERO);
        assert_eq!(t.sample(Vec2::new(0.75, 0.5)), Vec4::ONE);
        assert_eq!(t.sample(Vec2::new(1.25, 7.5)), Vec4::ZERO, "repeats");
        assert_eq!(t.sample(Vec2::new(f32::NAN, 0.5)), Vec4::ZERO);
    }

    #[test]
    fn linear_interpolates_between_texel_centres() {
        let t = two_by_one(Filter::Linear, Wrap::ClampToEdge);
        assert_eq!(t.sample(Vec2::new(0.5, 0.5)), Vec4::splat(0.5));
        assert_eq!(t.sample(Vec2::new(0.0, 0.5)), Vec4::ZERO, "clamped at the edge");
        assert_eq!(t.sample(Vec2::new(1.0, 0.5)), Vec4::ONE);
        let r = two_by_one(Filter::Linear, Wrap::Repeat);
        assert_eq!(r.sample(Vec2::new(0.0, 0.5)), Vec4::splat(0.5), "wraps around");
    }

    #[test]
    fn mirrored_repeat_reflects_every_other_copy() {
        assert_eq!((-3..5).map(|i| wrap(i, 2, Wrap::MirroredRepeat)).collect::<Vec<_>>(), [1, 1, 0, 0, 1, 1, 0, 0]);
        assert_eq!((-2..3).map(|i| wrap(i, 2, Wrap::ClampToEdge)).collect::<Vec<_>>(), [0, 0, 0, 1, 1]);
    }

    #[test]
    fn srgb_round_numbers() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214).abs() < 1e-3);
    }
}
