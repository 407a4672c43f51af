//! Exact box-filtered pixel coverage (001 §3): a convex polygon of the image plane cut into its
//! parts within each pixel square. Pixels the polygon covers wholly are found a row at a time from
//! its edges, without clipping; only the pixels its edges cross are clipped.

use beam_math::glam::{DVec3, Vec2};
use beam_math::polybeam::{BeamFrame, Section};

/// The affine map between image-plane coordinates and pixel coordinates (pixel `(x, y)` is the
/// unit square at `(x, y)`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PixelGrid {
    scale: Vec2,
    offset: Vec2,
}

impl PixelGrid {
    /// The grid of a `width × height` image spanning `[−hw, hw] × [−hh, hh]` of the image plane.
    pub(crate) fn new(hw: f32, hh: f32, width: u32, height: u32) -> Self {
        let offset = 0.5 * Vec2::new(width as f32, height as f32);
        Self { scale: offset / Vec2::new(hw, hh), offset }
    }

    pub(crate) fn to_pixels(self, c: Vec2) -> Vec2 {
        c * self.scale + self.offset
    }

    pub(crate) fn to_image(self, p: Vec2) -> Vec2 {
        (p - self.offset) / self.scale
    }

    /// `[d0, du, dv]`: the direction from `frame`'s apex to the image point of pixel point `m`
    /// is `d0 + m.x·du + m.y·dv` (in double precision).
    pub(crate) fn view_rays(self, frame: &BeamFrame) -> [DVec3; 3] {
        let (du, dv) = (frame.u.as_dvec3() / f64::from(self.scale.x), frame.v.as_dvec3() / f64::from(self.scale.y));
        let d0 = (frame.origin - frame.apex).as_dvec3() - f64::from(self.offset.x) * du - f64::from(self.offset.y) * dv;
        [d0, du, dv]
    }
}

/// The unit square of pixel `(x, y)`, counter-clockwise.
fn square(x: f32, y: f32) -> Section {
    let mut s = Section::new();
    for c in [Vec2::new(x, y), Vec2::new(x + 1.0, y), Vec2::new(x + 1.0, y + 1.0), Vec2::new(x, y + 1.0)] {
        // Four corners always fit.
        let _ = s.push(c);
    }
    s
}

/// Calls `f(x, y, coverage, part)` for every pixel of `[x0, x1) × [y0, y1)` that `section`
/// (image-plane coordinates) covers with positive area: `part` is the section ∩ pixel in pixel
/// coordinates and `coverage` its area, the pixel's box-filter weight.
pub(crate) fn pixel_parts(
    grid: PixelGrid,
    section: &Section,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
    mut f: impl FnMut(u32, u32, f32, &Section),
) {
    let mut p = Section::new();
    for &c in section.vertices() {
        // Same capacity as the section.
        let _ = p.push(grid.to_pixels(c));
    }
    let sign = p.signed_area().signum();
    if p.len() < 3 || sign == 0.0 {
        return;
    }
    let (lo, hi) = p.bounds();
    let rows = (lo.y.floor().max(y0 as f32), hi.y.ceil().min(y1 as f32));
    let v = p.vertices();
    let mut y = rows.0;
    while y < rows.1 {
        let (top, bottom) = (y, y + 1.0);
        // The polygon within the row.
        let strip = p.clip(Vec2::new(0.0, top), Vec2::NEG_Y).and_then(|s| s.clip(Vec2::new(0.0, bottom), Vec2::Y));
        let Ok(strip) = strip else {
            y += 1.0;
            continue;
        };
        if strip.len() >= 3 {
            // Columns whose square lies inside every edge's half-plane at both row lines: `x ≥ left`
            // and `x + 1 ≤ right` (the inside of a counter-clockwise edge a→b is to its left).
            let (mut left, mut right) = (f32::NEG_INFINITY, f32::INFINITY);
            for i in 0..v.len() {
                let (a, e) = (v[i], sign * (v[(i + 1) % v.len()] - v[i]));
                for yy in [top, bottom] {
                    if e.y > 0.0 {
                        right = right.min(a.x + e.x * (yy - a.y) / e.y);
                    } else if e.y < 0.0 {
                        left = left.max(a.x + e.x * (yy - a.y) / e.y);
                    } else if e.x * (yy - a.y) < 0.0 {
                        left = f32::INFINITY;
                    }
                }
            }
            // Within the bounding box too, which keeps a sliver whose rounded corners are not
            // quite convex from claiming pixels.
            if top < lo.y || bottom > hi.y {
                left = f32::INFINITY;
            }
            let (full0, full1) = (left.max(lo.x).ceil(), right.min(hi.x).floor() - 1.0);
            let (slo, shi) = strip.bounds();
            let mut x = slo.x.floor().max(x0 as f32);
            let x_end = shi.x.ceil().min(x1 as f32);
            while x < x_end {
                if x >= full0 && x <= full1 {
                    f(x as u32, y as u32, 1.0, &square(x, y));
                } else {
                    let part = strip
                        .clip(Vec2::new(x, 0.0), Vec2::NEG_X)
                        .and_then(|s| s.clip(Vec2::new(x + 1.0, 0.0), Vec2::X));
                    if let Ok(part) = part {
                        let area = part.area();
                        if area > 0.0 {
                            f(x as u32, y as u32, area, &part);
                        }
                    }
                }
                x += 1.0;
            }
        }
        y += 1.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The coverage of any convex polygon sums to its area in pixels, whole pixels get exactly 1,
    /// and each part lies in its pixel.
    #[test]
    fn parts_sum_to_the_polygon_and_whole_pixels_are_whole() {
        let grid = PixelGrid::new(1.0, 1.0, 20, 20);
        let shapes: [&[Vec2]; 3] = [
            &[Vec2::new(-0.93, -0.71), Vec2::new(0.88, -0.52), Vec2::new(0.1, 0.97)],
            &[Vec2::new(-0.5, -0.5), Vec2::new(0.5, -0.5), Vec2::new(0.5, 0.5), Vec2::new(-0.5, 0.5)],
            &[Vec2::new(0.3, 0.9), Vec2::new(-0.77, 0.13), Vec2::new(0.2, -0.99), Vec2::new(0.9, 0.05)],
        ];
        for shape in shapes {
            for reversed in [false, true] {
                let mut pts = shape.to_vec();
                if reversed {
                    pts.reverse();
                }
                let section = Section::from_slice(&pts).unwrap();
                let want = section.area() * 100.0;
                let (mut sum, mut whole) = (0.0f64, 0);
                pixel_parts(grid, &section, (0, 0, 20, 20), |x, y, cov, part| {
                    sum += f64::from(cov);
                    assert!((part.area() - cov).abs() < 1e-4);
                    let (lo, hi) = part.bounds();
                    assert!(lo.x >= x as f32 - 1e-4 && hi.x <= x as f32 + 1.0 + 1e-4);
                    assert!(lo.y >= y as f32 - 1e-4 && hi.y <= y as f32 + 1.0 + 1e-4);
                    if cov == 1.0 {
                        whole += 1;
                    }
                });
                assert!((sum - f64::from(want)).abs() < 1e-3, "{sum} vs {want}");
                assert!(whole > 0);
            }
        }
        // The square [-0.5, 0.5]² is pixels 5..15 exactly: 100 whole pixels and nothing else.
        let sq =
            Section::from_slice(&[Vec2::splat(-0.5), Vec2::new(0.5, -0.5), Vec2::splat(0.5), Vec2::new(-0.5, 0.5)])
                .unwrap();
        let mut n = 0;
        pixel_parts(grid, &sq, (0, 0, 20, 20), |x, y, cov, _| {
            assert!(cov == 1.0 && (5..15).contains(&x) && (5..15).contains(&y));
            n += 1;
        });
        assert_eq!(n, 100);
        // Restricted to a window, only its pixels come.
        pixel_parts(grid, &sq, (7, 8, 9, 10), |x, y, _, _| assert!((7..9).contains(&x) && (8..10).contains(&y)));
    }
}
