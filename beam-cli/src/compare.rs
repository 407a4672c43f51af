//! `beam compare`: RMSE and PSNR of two images, and `a | b | error map` beside each other.
//!
//! The headers are read first: the sizes must match and the memory fit ([`crate::limits`]). The
//! images are then held as 8-bit RGB (3 bytes a pixel each, not 12 as linear `f32`), the error map is
//! made a band of rows at a time, and the inputs are dropped before the output is encoded.

use crate::limits;
use crate::output::check_png_name;
use beam_cpu::render::side_by_side;
use beam_math::glam::Vec3;
use beam_render::image::{Image, srgb_decode, srgb_encode};
use beam_scene::io::{check_output, encode_png, same_file, write_atomic};
use image::{ImageDecoder, ImageReader, Limits};
use std::path::Path;
use std::process::ExitCode;

/// Rows of the error map made at a time.
const BAND: u32 = 64;

/// A checked comparison: the input sizes and the bytes each decodes to.
pub(crate) struct ComparePlan {
    pub width: u32,
    pub height: u32,
}

/// An input's header: size and decoded bytes. Refuses what is not a regular file before opening it.
fn header(path: &Path) -> Result<(u32, u32, u64), String> {
    let fail = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let meta = std::fs::metadata(path).map_err(|e| fail(&e))?;
    if !meta.is_file() {
        return Err(fail(&"not a regular file"));
    }
    let decoder = ImageReader::open(path)
        .and_then(ImageReader::with_guessed_format)
        .map_err(|e| fail(&e))?
        .into_decoder()
        .map_err(|e| fail(&e))?;
    let (w, h) = decoder.dimensions();
    Ok((w, h, decoder.total_bytes()))
}

/// Check both inputs' headers, the output path and the memory, before decoding anything.
pub(crate) fn plan(a: &Path, b: &Path, out: &Path, scale: f32, quiet: bool) -> Result<ComparePlan, String> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(format!("--scale {scale}: expected a positive number"));
    }
    check_png_name("--out", out)?;
    for input in [a, b] {
        if same_file(out, input) {
            return Err(format!("--out {} would replace the input {}", out.display(), input.display()));
        }
    }
    let (wa, ha, bytes_a) = header(a)?;
    let (wb, hb, bytes_b) = header(b)?;
    if (wa, ha) != (wb, hb) {
        return Err(format!("{} vs {}: sizes differ: {wa}×{ha} and {wb}×{hb}", a.display(), b.display()));
    }
    let too_wide = u64::from(wa) * 3 > u64::from(u32::MAX);
    if wa == 0 || ha == 0 || too_wide {
        return Err(format!("{}: a {wa}×{ha} image cannot be compared side by side", a.display()));
    }
    check_output(out).map_err(|e| format!("--out {e}"))?;
    let pixels = u64::from(wa) * u64::from(ha);
    // Both inputs at 3 bytes a pixel, the larger decoded buffer while it converts, the 9-byte output
    // row set and its encoding (at most about as large), and a band of linear pixels.
    let memory = limits::bytes(&[
        (pixels, 6),
        (bytes_a.max(bytes_b), 1),
        (pixels, 18),
        (u64::from(wa) * u64::from(BAND), 5 * 12),
        (1, 32 << 20),
    ]);
    limits::admit(&format!("comparing two {wa}×{ha} images"), memory, quiet)?;
    Ok(ComparePlan { width: wa, height: ha })
}

/// Decode `path` to 8-bit RGB (alpha dropped, grey replicated, 16-bit rounded).
fn load_rgb8(path: &Path) -> Result<image::RgbImage, String> {
    let fail = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let mut reader = ImageReader::open(path).and_then(ImageReader::with_guessed_format).map_err(|e| fail(&e))?;
    // The memory was checked against our own limit; the crate's default (512 MiB) would refuse less.
    reader.limits(Limits::no_limits());
    Ok(reader.decode().map_err(|e| fail(&e))?.into_rgb8())
}

/// RMSE, PSNR and the largest channel difference of two 8-bit sRGB buffers of one size, exactly as
/// [`beam_cpu::render::difference`] computes them on the images read back to linear.
fn metrics(a: &[u8], b: &[u8]) -> (f64, f64, f64) {
    // The sRGB value each byte reads back as, exactly as a linear image encodes it again.
    let lut: [f32; 256] = std::array::from_fn(|i| srgb_encode(srgb_decode(i as f32 / 255.0)));
    let (mut sum, mut max) = (0.0f64, 0.0f64);
    for (p, q) in a.iter().zip(b) {
        let d = f64::from(lut[*p as usize] - lut[*q as usize]);
        sum += d * d;
        max = max.max(d.abs());
    }
    let rmse = (sum / a.len().max(1) as f64).sqrt();
    (rmse, if rmse > 0.0 { 20.0 * (1.0 / rmse).log10() } else { f64::INFINITY }, max)
}

/// `a | b | error map` as 8-bit sRGB, made [`BAND`] rows at a time by [`side_by_side`].
fn picture(a: &image::RgbImage, b: &image::RgbImage, scale: f32) -> Result<Vec<u8>, String> {
    let (w, h) = a.dimensions();
    let linear = |img: &image::RgbImage, y0: u32, rows: u32| {
        let row = 3 * w as usize;
        let bytes = &img.as_raw()[y0 as usize * row..(y0 + rows) as usize * row];
        let pixels =
            bytes.chunks_exact(3).map(|c| Vec3::from_array([0, 1, 2].map(|k| srgb_decode(c[k] as f32 / 255.0))));
        Image { width: w, height: rows, pixels: pixels.collect() }
    };
    let mut rgb = Vec::with_capacity(9 * w as usize * h as usize);
    for y0 in (0..h).step_by(BAND as usize) {
        let rows = BAND.min(h - y0);
        rgb.extend(
            side_by_side(&linear(a, y0, rows), &linear(b, y0, rows), scale).map_err(|e| e.to_string())?.to_srgb8(),
        );
    }
    Ok(rgb)
}

pub(crate) fn compare(a: &Path, b: &Path, out: &Path, scale: f32) -> Result<ExitCode, String> {
    let plan = plan(a, b, out, scale, false)?;
    let (ia, ib) = (load_rgb8(a)?, load_rgb8(b)?);
    if ia.dimensions() != (plan.width, plan.height) || ib.dimensions() != (plan.width, plan.height) {
        return Err(format!("{} or {} changed while being read", a.display(), b.display()));
    }
    let (rmse, psnr, max) = metrics(ia.as_raw(), ib.as_raw());
    let rgb = picture(&ia, &ib, scale)?;
    drop((ia, ib));
    let png = encode_png(3 * plan.width, plan.height, &rgb).map_err(|e| format!("{}: {e}", out.display()))?;
    drop(rgb);
    write_atomic(out, &png).map_err(|e| e.to_string())?;
    println!("RMSE {rmse:.5}  PSNR {psnr:.2} dB  max {max:.4}  (sRGB, [0, 1]) -> {}", out.display());
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_cpu::render::difference;

    /// The 8-bit path gives what the linear images gave, to the bit.
    #[test]
    fn same_figures_and_picture_as_linear_images() {
        let (w, h) = (37, 70);
        let bytes = |k: u32| (0..w * h * 3).map(|i: u32| (i.wrapping_mul(k) >> 3) as u8).collect::<Vec<u8>>();
        let (a, b) = (bytes(2_654_435_761), bytes(40_503));
        let linear = |v: &[u8]| Image {
            width: w,
            height: h,
            pixels: v
                .chunks_exact(3)
                .map(|c| Vec3::from_array([0, 1, 2].map(|k| srgb_decode(c[k] as f32 / 255.0))))
                .collect(),
        };
        let (la, lb) = (linear(&a), linear(&b));
        let d = difference(&la, &lb).unwrap();
        let (rmse, psnr, max) = metrics(&a, &b);
        assert_eq!((rmse, psnr, max), (d.rmse, d.psnr, d.max));
        let (ia, ib) =
            (image::RgbImage::from_raw(w, h, a.clone()).unwrap(), image::RgbImage::from_raw(w, h, b.clone()).unwrap());
        assert_eq!(picture(&ia, &ib, 0.1).unwrap(), side_by_side(&la, &lb, 0.1).unwrap().to_srgb8());
    }
}
