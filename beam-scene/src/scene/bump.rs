//! An OBJ material's bump map as the tangent-space normal map the shading reads
//! ([`NormalMap`](super::surface::NormalMap)): a grey image is a height map, turned into normals by
//! central differences; an image whose mean texel is about (0.5, 0.5, 1) is a normal map already
//! (Blender writes its normal maps as `map_Bump`), used as it is.

use std::sync::Arc;

/// Whether the 8-bit RGBA `texels` are a tangent-space normal map rather than heights: their mean
/// lies within 0.15 of (0.5, 0.5, 1) (flat normals; a height map is grey, its channels equal).
pub(crate) fn is_normal_map(texels: &[[u8; 4]]) -> bool {
    if texels.is_empty() {
        return false;
    }
    let mut sum = [0u64; 3];
    for t in texels {
        for (s, &c) in sum.iter_mut().zip(t) {
            *s += u64::from(c);
        }
    }
    let mean = sum.map(|s| s as f32 / (255.0 * texels.len() as f32));
    let flat = [0.5, 0.5, 1.0];
    mean.iter().zip(flat).all(|(m, f)| (m - f).abs() <= 0.15)
}

/// The tangent-space normal map of the height map `texels` (`width × height`, rows from the top;
/// a texel's height is the mean of its colour channels, `code / 255`), its heights scaled by
/// `scale` (`-bm`): at each texel `n = normalize(−s ∂h/∂x, s ∂h/∂y, 1)`, the derivatives central
/// differences in texels (`x` right, `y` down the image; the map's `y` points up it), wrapping
/// at the edges as the texture repeats; encoded `(n + 1) / 2 · 255`, alpha 255. A step from 0 to 1
/// over one texel at `scale` 1 tilts the normal by about 27°.
pub(crate) fn height_to_normals(width: u32, height: u32, texels: &[[u8; 4]], scale: f32) -> Arc<[[u8; 4]]> {
    let (w, h) = (width as usize, height as usize);
    debug_assert_eq!(texels.len(), w * h);
    let heights: Vec<f32> =
        texels.iter().map(|t| (f32::from(t[0]) + f32::from(t[1]) + f32::from(t[2])) / (3.0 * 255.0)).collect();
    let at = |x: usize, y: usize| heights[y * w + x];
    let encode = |c: f32| ((c + 1.0) * 0.5 * 255.0).round().clamp(0.0, 255.0) as u8;
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let dx = 0.5 * (at((x + 1) % w, y) - at((x + w - 1) % w, y));
            let dy = 0.5 * (at(x, (y + 1) % h) - at(x, (y + h - 1) % h));
            let (nx, ny, nz) = (-scale * dx, scale * dy, 1.0);
            let len = (nx * nx + ny * ny + nz * nz).sqrt();
            out.push([encode(nx / len), encode(ny / len), encode(nz / len), 255]);
        }
    }
    out.into()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(t: [u8; 4]) -> [f32; 3] {
        [0, 1, 2].map(|i| f32::from(t[i]) / 255.0 * 2.0 - 1.0)
    }

    #[test]
    fn a_ramp_tilts_the_normal_against_its_slope() {
        // Heights rising by 1/8 a texel to the right (wrapping once across 8 texels), flat down.
        let w = 8;
        let texels: Vec<[u8; 4]> = (0..w * 2)
            .map(|i| {
                let h = (i % w) as f32 / w as f32;
                let c = (h * 255.0).round() as u8;
                [c, c, c, 255]
            })
            .collect();
        let n = height_to_normals(w as u32, 2, &texels, 2.0);
        // Inside the ramp: ∂h/∂x = 1/8, so n ∝ (−2/8, 0, 1).
        let expect = {
            let l = (0.25f32 * 0.25 + 1.0).sqrt();
            [-0.25 / l, 0.0, 1.0 / l]
        };
        for x in 1..w - 1 {
            let got = decode(n[w + x]);
            for (g, e) in got.iter().zip(expect) {
                assert!((g - e).abs() < 0.01, "texel {x}: {got:?}, not {expect:?}");
            }
        }
        // A flat map points straight out; heights rising down the image tilt the normal up it.
        let flat = height_to_normals(2, 2, &[[90, 90, 90, 255]; 4], 1.0);
        assert!(flat.iter().all(|&t| t == [128, 128, 255, 255]), "{flat:?}");
        let down: Vec<[u8; 4]> = [0u8, 0, 0, 40, 40, 40, 80, 80, 80].iter().map(|&c| [c, c, c, 255]).collect();
        let n = decode(height_to_normals(3, 3, &down, 4.0)[4]);
        assert!(n[1] > 0.2 && n[0].abs() < 0.01, "{n:?}");
    }

    #[test]
    fn normal_maps_and_height_maps_are_told_apart() {
        assert!(is_normal_map(&[[128, 128, 255, 255], [120, 135, 250, 255]]));
        assert!(!is_normal_map(&[[128, 128, 128, 255], [200, 200, 200, 255]]), "grey heights");
        assert!(!is_normal_map(&[[250, 250, 250, 255]]), "white heights");
        assert!(!is_normal_map(&[]));
    }
}
