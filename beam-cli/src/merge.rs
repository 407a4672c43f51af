//! `beam merge`: the tiles of `beam render --tile` or `--crop` joined into the whole frame.
//!
//! Every tile's header is read first (its place in the frame: a PNG's `beam:region` chunk, an EXR's
//! data and display windows; a file without one is a whole frame): the tiles must share the frame's
//! size, not overlap and cover it, and the memory must fit ([`crate::limits`]), before any pixel
//! is decoded. The whole frame is then encoded as a one-process render encodes it, so the two
//! files are the same byte for byte.

use crate::limits;
use crate::output::Format;
use crate::plan::MAX_SIDE;
use beam_math::glam::Vec3;
use beam_scene::io::{
    check_output, encode_exr, encode_png, read_exr, read_exr_placement, read_png_placed, read_png_placement, same_file,
    write_atomic,
};
use beam_scene::region::{PixelRect, Placement};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A checked merge: the format, the frame and each tile's place in it.
pub(crate) struct MergePlan {
    pub format: Format,
    pub width: u32,
    pub height: u32,
    pub tiles: Vec<(PathBuf, Placement)>,
}

/// Check the output path, every tile's header and the memory, before decoding anything.
pub(crate) fn plan(tiles: &[PathBuf], out: &Path, quiet: bool) -> Result<MergePlan, String> {
    let format = Format::of("--out", out)?;
    let first = tiles.first().ok_or("no tile to merge")?;
    for t in tiles {
        let f = Format::of("a tile", t)?;
        if f != format {
            return Err(format!(
                "tile {} is {} but --out {} is {}: merge tiles into their own format",
                t.display(),
                f.name(),
                out.display(),
                format.name()
            ));
        }
        if same_file(out, t) {
            return Err(format!("--out {} would replace the tile {}", out.display(), t.display()));
        }
    }
    check_output(out).map_err(|e| format!("--out {e}"))?;
    let placed: Vec<(PathBuf, Placement)> = tiles
        .iter()
        .map(|t| {
            let p = match format {
                Format::Png => read_png_placement(t),
                Format::Exr => read_exr_placement(t),
            };
            p.map(|p| (t.clone(), p)).map_err(|e| e.to_string())
        })
        .collect::<Result<_, _>>()?;
    let frame = |p: &Placement| (p.frame_width, p.frame_height);
    let (width, height) = frame(&placed[0].1);
    if let Some((t, p)) = placed.iter().find(|(_, p)| frame(p) != (width, height)) {
        return Err(format!(
            "the tiles are of different frames: {} is part of a {width}×{height} frame, {} of a {}×{} one",
            first.display(),
            t.display(),
            p.frame_width,
            p.frame_height
        ));
    }
    if let Some((t, _)) = placed.iter().find(|(_, p)| p.render != placed[0].1.render) {
        return Err(format!(
            "{} and {} are tiles of different renders (another scene, method, option, --frame or \
             --exposure): merge the tiles of one render",
            first.display(),
            t.display()
        ));
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(format!(
            "{}: a {width}×{height} frame is larger than beam renders (each side at most {MAX_SIDE})",
            first.display()
        ));
    }
    check_tiling(&placed, width, height)?;
    let bytes_per_pixel = match format {
        Format::Png => 3,
        Format::Exr => 12,
    };
    let pixels = u64::from(width) * u64::from(height);
    let largest = placed.iter().map(|(_, p)| p.rect.len() as u64).max().unwrap_or(0);
    // The frame's pixels, its encoding (at most about as large), and the largest tile decoded.
    let memory = limits::bytes(&[(pixels, 2 * bytes_per_pixel), (largest, bytes_per_pixel), (1, 32 << 20)]);
    limits::admit(&format!("merging a {width}×{height} frame"), memory, quiet)?;
    Ok(MergePlan { format, width, height, tiles: placed })
}

/// The tiles must not overlap and must cover the `width × height` frame; the errors name the tiles
/// that overlap, or pixels no tile holds.
fn check_tiling(tiles: &[(PathBuf, Placement)], width: u32, height: u32) -> Result<(), String> {
    let mut sorted: Vec<&(PathBuf, Placement)> = tiles.iter().collect();
    sorted.sort_by_key(|(_, p)| (p.rect.y0, p.rect.x0));
    for (i, (a, pa)) in sorted.iter().enumerate() {
        // Sorted by first row: only the tiles that start before `a` ends can overlap it.
        for (b, pb) in sorted[i + 1..].iter().take_while(|(_, pb)| pb.rect.y0 < pa.rect.y1) {
            if pa.rect.overlaps(pb.rect) {
                return Err(format!(
                    "tiles {} ({}) and {} ({}) overlap in {}",
                    a.display(),
                    pa.rect,
                    b.display(),
                    pb.rect,
                    pa.rect.intersect(pb.rect)
                ));
            }
        }
    }
    let covered: u64 = tiles.iter().map(|(_, p)| p.rect.len() as u64).sum();
    if covered == u64::from(width) * u64::from(height) {
        return Ok(());
    }
    // Not overlapping and not covering: find a gap, in a band of rows between tile edges.
    let mut edges: Vec<u32> = tiles.iter().flat_map(|(_, p)| [p.rect.y0, p.rect.y1]).chain([0, height]).collect();
    edges.sort_unstable();
    edges.dedup();
    for band in edges.windows(2) {
        let (y0, y1) = (band[0], band[1]);
        let mut spans: Vec<(u32, u32)> = tiles
            .iter()
            .filter(|(_, p)| p.rect.y0 <= y0 && p.rect.y1 >= y1)
            .map(|(_, p)| (p.rect.x0, p.rect.x1))
            .collect();
        spans.sort_unstable();
        let mut x = 0;
        for (x0, x1) in spans.into_iter().chain([(width, width)]) {
            if x0 > x {
                let gap = PixelRect { x0: x, y0, x1: x0, y1 };
                return Err(format!(
                    "the tiles do not cover the {width}×{height} frame: no tile holds {gap} (a tile is missing)"
                ));
            }
            x = x.max(x1);
        }
    }
    Err(format!("the tiles do not cover the {width}×{height} frame"))
}

/// Decode every tile into the frame and write it.
pub(crate) fn merge(tiles: &[PathBuf], out: &Path) -> Result<ExitCode, String> {
    let plan = plan(tiles, out, false)?;
    let (w, h) = (plan.width, plan.height);
    let bytes = match plan.format {
        Format::Png => {
            let mut frame = vec![0u8; w as usize * h as usize * 3];
            for (path, planned) in &plan.tiles {
                let rgb = read_png_placed(path, *planned).map_err(|e| e.to_string())?;
                paste(&rgb, planned.rect, &mut frame, w, 3);
            }
            encode_png(w, h, &frame)
        }
        Format::Exr => {
            let mut frame = vec![Vec3::ZERO; w as usize * h as usize];
            for (path, planned) in &plan.tiles {
                let pixels = read_exr(path, *planned).map_err(|e| e.to_string())?;
                paste(&pixels, planned.rect, &mut frame, w, 1);
            }
            encode_exr(&frame, Placement::whole(w, h))
        }
    };
    let bytes = bytes.map_err(|e| format!("{}: {e}", out.display()))?;
    write_atomic(out, &bytes).map_err(|e| e.to_string())?;
    println!("{} tiles merged into the {w}×{h} frame -> {}", plan.tiles.len(), out.display());
    Ok(ExitCode::SUCCESS)
}

/// Copy a tile's row-major `values` (`per` values a pixel, the pixels of `rect`) into `frame`, a
/// row-major frame `width` pixels wide.
fn paste<T: Copy>(values: &[T], rect: PixelRect, frame: &mut [T], width: u32, per: usize) {
    let row = rect.width() as usize * per;
    for (i, y) in (rect.y0..rect.y1).enumerate() {
        let to = (y as usize * width as usize + rect.x0 as usize) * per;
        frame[to..to + row].copy_from_slice(&values[i * row..(i + 1) * row]);
    }
}
