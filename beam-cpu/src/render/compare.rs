//! Image comparison: RMSE and PSNR on 8-bit sRGB values, and a side-by-side picture with an error map.

use crate::RenderError;
use beam_math::glam::Vec3;
use beam_render::image::{Image, srgb_decode, srgb_encode};

/// Differences between two images of the same size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Difference {
    /// Root-mean-square error of the sRGB values in `[0, 1]`, over all channels.
    pub rmse: f64,
    /// `20·log10(1/RMSE)` in dB (infinite for identical images).
    pub psnr: f64,
    /// Largest per-channel absolute difference.
    pub max: f64,
}

/// Compare `a` and `b` (same size) on their sRGB encodings.
pub fn difference(a: &Image, b: &Image) -> Result<Difference, RenderError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(RenderError::SizeMismatch { first: (a.width, a.height), second: (b.width, b.height) });
    }
    let (mut sum, mut max) = (0.0f64, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for k in 0..3 {
            let d = f64::from(srgb_encode(p[k]) - srgb_encode(q[k]));
            sum += d * d;
            max = max.max(d.abs());
        }
    }
    let rmse = (sum / (3 * a.pixels.len()).max(1) as f64).sqrt();
    Ok(Difference { rmse, psnr: if rmse > 0.0 { 20.0 * (1.0 / rmse).log10() } else { f64::INFINITY }, max })
}

/// A false-colour ramp (black → blue → red → yellow → white) of `x ∈ [0, 1]`, in sRGB.
fn heat(x: f32) -> Vec3 {
    let stops = [Vec3::ZERO, Vec3::new(0.1, 0.2, 0.9), Vec3::new(0.9, 0.1, 0.1), Vec3::new(1.0, 0.9, 0.1), Vec3::ONE];
    let t = x.clamp(0.0, 1.0) * (stops.len() - 1) as f32;
    let i = (t as usize).min(stops.len() - 2);
    stops[i].lerp(stops[i + 1], t - i as f32)
}

/// `a | b | error map`: the error map shows the largest channel difference of each pixel, scaled so
/// that `scale` (in sRGB units) is full scale.
pub fn side_by_side(a: &Image, b: &Image, scale: f32) -> Result<Image, RenderError> {
    difference(a, b)?;
    let (w, h) = (a.width, a.height);
    let mut out = Image::new(3 * w, h);
    for y in 0..h as usize {
        for x in 0..w as usize {
            let i = y * w as usize + x;
            let row = y * 3 * w as usize;
            out.pixels[row + x] = a.pixels[i];
            out.pixels[row + w as usize + x] = b.pixels[i];
            let d = (0..3)
                .map(|k| (srgb_encode(a.pixels[i][k]) - srgb_encode(b.pixels[i][k])).abs())
                .fold(0.0f32, f32::max);
            out.pixels[row + 2 * w as usize + x] = heat(d / scale.max(1e-6)).to_array().map(srgb_decode).into();
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_and_different() {
        let a = Image::new(4, 4);
        assert_eq!(difference(&a, &a).unwrap().rmse, 0.0);
        let mut b = a.clone();
        b.pixels[0] = Vec3::ONE;
        let d = difference(&a, &b).unwrap();
        assert!((d.rmse - (3.0f64 / 48.0).sqrt()).abs() < 1e-6 && (d.max - 1.0).abs() < 1e-6, "{d:?}");
        assert_eq!(side_by_side(&a, &b, 0.1).unwrap().width, 12);
        assert!(difference(&a, &Image::new(2, 2)).is_err());
    }
}
