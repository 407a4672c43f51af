//! The part of the frame `beam render` computes: `--tile I/N` (band I of N horizontal bands, the
//! same split in every process) or `--crop x0,y0,x1,y1` (a pixel rectangle, half-open), checked
//! against the image size with errors that name the option.

use beam_scene::region::PixelRect;

/// The rectangle `--tile` or `--crop` names in a `width × height` image (`None`: the whole frame).
pub(crate) fn parse(
    tile: Option<&str>,
    crop: Option<&str>,
    width: u32,
    height: u32,
) -> Result<Option<PixelRect>, String> {
    match (tile, crop) {
        (Some(_), Some(_)) => Err("give --tile or --crop, not both".into()),
        (Some(t), None) => tile_rect(t, width, height).map(Some),
        (None, Some(c)) => crop_rect(c, width, height).map(Some),
        (None, None) => Ok(None),
    }
}

/// `--tile I/N`: band `I` (0 to N − 1) of `N` horizontal bands, rows `⌊I·H/N⌋ .. ⌊(I+1)·H/N⌋`.
fn tile_rect(text: &str, width: u32, height: u32) -> Result<PixelRect, String> {
    let shown = shown(text);
    let (i, n) = text
        .split_once('/')
        .and_then(|(i, n)| Some((i.trim().parse::<u32>().ok()?, n.trim().parse::<u32>().ok()?)))
        .ok_or_else(|| format!("--tile {shown}: expected I/N, band I (0 to N − 1) of N, such as 3/16"))?;
    if n == 0 {
        return Err(format!("--tile {shown}: the frame needs at least one band (N ≥ 1)"));
    }
    if i >= n {
        return Err(format!("--tile {shown}: band {i} does not exist; the bands of {n} are 0 to {}", n - 1));
    }
    PixelRect::band(i, n, width, height).ok_or_else(|| {
        format!("--tile {shown}: {n} bands of a {height}-row image would leave some empty (at most {height} bands)")
    })
}

/// `--crop x0,y0,x1,y1`: the pixels `[x0, x1) × [y0, y1)`, non-empty and inside the image.
fn crop_rect(text: &str, width: u32, height: u32) -> Result<PixelRect, String> {
    let shown = shown(text);
    let v: Option<Vec<u32>> = text.split(',').map(|s| s.trim().parse().ok()).collect();
    let Some(&[x0, y0, x1, y1]) = v.as_deref() else {
        return Err(format!(
            "--crop {shown}: expected x0,y0,x1,y1, the pixels x0 ≤ x < x1 and y0 ≤ y < y1, such as 0,0,64,32"
        ));
    };
    if x0 >= x1 || y0 >= y1 {
        return Err(format!("--crop {shown}: the rectangle is empty (it needs x0 < x1 and y0 < y1)"));
    }
    let r = PixelRect { x0, y0, x1, y1 };
    if !r.fits(width, height) {
        return Err(format!(
            "--crop {shown}: reaches past the {width}×{height} image (x1 ≤ {width} and y1 ≤ {height}; x1 and y1 \
             are one past the last column and row)"
        ));
    }
    Ok(r)
}

/// `text` for an error message: at most 40 characters, control characters escaped.
fn shown(text: &str) -> String {
    beam_scene::read::visible(&beam_scene::read::clip(text, 40))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_and_crops_are_checked() {
        assert_eq!(parse(Some("1/4"), None, 64, 48), Ok(Some(PixelRect { x0: 0, y0: 12, x1: 64, y1: 24 })));
        assert_eq!(parse(None, Some("1, 2,3,4"), 64, 48), Ok(Some(PixelRect { x0: 1, y0: 2, x1: 3, y1: 4 })));
        assert_eq!(parse(None, None, 64, 48), Ok(None));
        for (tile, crop, says) in [
            (Some("4/4"), None, "band 4 does not exist; the bands of 4 are 0 to 3"),
            (Some("0/0"), None, "at least one band"),
            (Some("0/49"), None, "at most 48 bands"),
            (Some("1"), None, "expected I/N"),
            (Some("-1/4"), None, "expected I/N"),
            (None, Some("0,0,65,48"), "reaches past the 64×48 image"),
            (None, Some("3,0,3,48"), "empty"),
            (None, Some("0,0,4"), "expected x0,y0,x1,y1"),
            (Some("0/1"), Some("0,0,1,1"), "not both"),
        ] {
            let e = parse(tile, crop, 64, 48).unwrap_err();
            assert!(e.contains(says), "{e}");
        }
    }
}
