//! Pixel rectangles of a frame: the part of the image a render computes (a render farm's tile or a
//! crop), and the even split of a frame into horizontal bands.

/// The pixels `[x0, x1) × [y0, y1)` of a frame, in the frame's own coordinates (origin at the
/// top-left pixel, y down). Empty when `x0 ≥ x1` or `y0 ≥ y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PixelRect {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelRect {
    /// The whole `width × height` frame.
    #[must_use]
    pub const fn full(width: u32, height: u32) -> Self {
        Self { x0: 0, y0: 0, x1: width, y1: height }
    }

    /// The pixels a render of a `width × height` frame computes: `region` within the frame, or the
    /// whole frame without one.
    #[must_use]
    pub fn rendered(region: Option<Self>, width: u32, height: u32) -> Self {
        let frame = Self::full(width, height);
        region.map_or(frame, |r| r.intersect(frame))
    }

    /// Columns (0 when empty).
    #[must_use]
    pub fn width(self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    /// Rows (0 when empty).
    #[must_use]
    pub fn height(self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }

    /// Pixels (0 when empty).
    #[must_use]
    pub fn len(self) -> usize {
        self.width() as usize * self.height() as usize
    }

    /// No pixel.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.len() == 0
    }

    /// Whether pixel `(x, y)` lies inside.
    #[must_use]
    pub fn contains(self, x: u32, y: u32) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }

    /// The pixels in both (possibly empty).
    #[must_use]
    pub fn intersect(self, o: Self) -> Self {
        Self { x0: self.x0.max(o.x0), y0: self.y0.max(o.y0), x1: self.x1.min(o.x1), y1: self.y1.min(o.y1) }
    }

    /// Whether `self` and `o` share a pixel.
    #[must_use]
    pub fn overlaps(self, o: Self) -> bool {
        !self.intersect(o).is_empty()
    }

    /// Whether the rectangle is non-empty and lies within a `width × height` frame.
    #[must_use]
    pub fn fits(self, width: u32, height: u32) -> bool {
        self.x0 < self.x1 && self.y0 < self.y1 && self.x1 <= width && self.y1 <= height
    }

    /// The smallest rectangle of whole `step × step` cells of the frame's grid (anchored at its
    /// corner, the last row and column of cells cut at the frame's edge) that holds `self`, within
    /// a `width × height` frame. A renderer whose pixels depend on their cell's other pixels
    /// computes this to give each pixel of `self` its whole-frame value.
    #[must_use]
    pub fn aligned_out(self, step: u32, width: u32, height: u32) -> Self {
        let step = step.max(1);
        let down = |v: u32| v / step * step;
        let up = |v: u32, end: u32| v.div_ceil(step).saturating_mul(step).min(end);
        Self { x0: down(self.x0), y0: down(self.y0), x1: up(self.x1, width), y1: up(self.y1, height) }
    }

    /// Band `index` of `count` horizontal bands of a `width × height` frame: rows
    /// `⌊index·height/count⌋ .. ⌊(index+1)·height/count⌋`, so that the bands' heights differ by at
    /// most one and every process that asks for the same split gets the same rows. `None` when
    /// `index ≥ count` or `count` is 0 or above `height` (a band would be empty).
    #[must_use]
    pub fn band(index: u32, count: u32, width: u32, height: u32) -> Option<Self> {
        if count == 0 || index >= count || count > height {
            return None;
        }
        let row = |i: u32| (u64::from(i) * u64::from(height) / u64::from(count)) as u32;
        Some(Self { x0: 0, y0: row(index), x1: width, y1: row(index + 1) })
    }

    /// Index of pixel `(x, y)` (inside) in a row-major buffer of the rectangle.
    #[must_use]
    pub fn index(self, x: u32, y: u32) -> usize {
        (y - self.y0) as usize * self.width() as usize + (x - self.x0) as usize
    }

    /// The row-major indices of the rectangle's pixels in a row-major buffer of a frame `width`
    /// pixels wide.
    pub fn frame_indices(self, width: u32) -> impl Iterator<Item = usize> {
        let (w, rows) = (width as usize, if self.is_empty() { 0..0 } else { self.y0..self.y1 });
        rows.flat_map(move |y| (self.x0..self.x1).map(move |x| y as usize * w + x as usize))
    }

    /// The rectangle's pixels cut out of a row-major buffer of a frame `width` pixels wide that holds
    /// it, row-major: the buffer itself when the rectangle is the whole frame (no copy).
    #[must_use]
    pub fn cut<T: Copy>(self, mut frame: Vec<T>, width: u32) -> Vec<T> {
        let w = width as usize;
        if self.x0 == 0 && self.y0 == 0 && self.x1 == width && self.y1 as usize * w == frame.len() {
            return frame;
        }
        if self.is_empty() {
            return Vec::new();
        }
        let (x0, x1) = (self.x0 as usize, self.x1 as usize);
        // Rows move down in place: row k's pixels go to k·(x1 − x0), never past where they are read.
        let mut end = 0;
        for y in self.y0 as usize..self.y1 as usize {
            frame.copy_within(y * w + x0..y * w + x1, end);
            end += x1 - x0;
        }
        frame.truncate(end);
        frame
    }
}

/// `pixels x0..x1 × y0..y1`, as error messages and reports name a rectangle.
impl core::fmt::Display for PixelRect {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "pixels {}..{} × {}..{}", self.x0, self.x1, self.y0, self.y1)
    }
}

/// Where an image's pixels sit in a larger frame: a render farm's tile is the pixels `rect` of a
/// `frame_width × frame_height` frame, of the render `render`. Image files carry it (see
/// [`crate::io`]) so that the tiles can be joined again, and only with tiles of the same render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Placement {
    /// The image's pixels in the frame (non-empty, within it).
    pub rect: PixelRect,
    /// Frame width.
    pub frame_width: u32,
    /// Frame height.
    pub frame_height: u32,
    /// Which render the pixels come from: a fingerprint of everything that decides their values
    /// (scene, method, options, frame, exposure), equal for every tile of one frame and different
    /// for tiles of another; 0 where no one said.
    pub render: u64,
}

impl Placement {
    /// `rect` of a `frame_width × frame_height` frame; `None` unless it is non-empty and within it.
    #[must_use]
    pub fn new(rect: PixelRect, frame_width: u32, frame_height: u32) -> Option<Self> {
        rect.fits(frame_width, frame_height).then_some(Self { rect, frame_width, frame_height, render: 0 })
    }

    /// A whole `width × height` frame.
    #[must_use]
    pub fn whole(width: u32, height: u32) -> Self {
        Self { rect: PixelRect::full(width, height), frame_width: width, frame_height: height, render: 0 }
    }

    /// The same placement, of the render `render` (see [`Self::render`]).
    #[must_use]
    pub fn of_render(self, render: u64) -> Self {
        Self { render, ..self }
    }

    /// Whether it is the whole frame.
    #[must_use]
    pub fn is_whole(&self) -> bool {
        self.rect == PixelRect::full(self.frame_width, self.frame_height)
    }

    /// `x0,y0,x1,y1,W,H,R` (R the render's fingerprint in hexadecimal): what [`Self::parse`] reads.
    #[must_use]
    pub fn to_text(&self) -> String {
        let r = self.rect;
        format!("{},{},{},{},{},{},{:016x}", r.x0, r.y0, r.x1, r.y1, self.frame_width, self.frame_height, self.render)
    }

    /// `x0,y0,x1,y1,W,H` (decimal, no spaces needed) and an optional `,R` (hexadecimal, else 0);
    /// `None` unless they make a valid placement.
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        let (numbers, render) = match fields.as_slice() {
            [n @ .., r] if n.len() == 6 => (n, u64::from_str_radix(r, 16).ok()?),
            n => (n, 0),
        };
        let v: Vec<u32> = numbers.iter().map(|s| s.parse().ok()).collect::<Option<_>>()?;
        let &[x0, y0, x1, y1, w, h] = v.as_slice() else { return None };
        Some(Self::new(PixelRect { x0, y0, x1, y1 }, w, h)?.of_render(render))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_split_evenly_and_cover_the_frame() {
        for (h, n) in [(48, 4), (48, 5), (7, 7), (1080, 16), (5, 3)] {
            let bands: Vec<_> = (0..n).map(|i| PixelRect::band(i, n, 9, h).unwrap()).collect();
            assert_eq!(bands[0].y0, 0);
            assert_eq!(bands[n as usize - 1].y1, h);
            for w in bands.windows(2) {
                assert_eq!(w[0].y1, w[1].y0);
            }
            let (lo, hi) = (h / n, h.div_ceil(n));
            assert!(bands.iter().all(|b| (lo..=hi).contains(&b.height())), "{bands:?}");
        }
        assert_eq!(PixelRect::band(4, 4, 9, 48), None);
        assert_eq!(PixelRect::band(0, 0, 9, 48), None);
        assert_eq!(PixelRect::band(0, 49, 9, 48), None);
        assert!(PixelRect::band(u32::MAX - 1, u32::MAX, 9, u32::MAX).is_some());
    }

    #[test]
    fn placements_round_trip_as_text() {
        let p = Placement::new(PixelRect { x0: 0, y0: 12, x1: 64, y1: 24 }, 64, 48).unwrap();
        assert_eq!(p.to_text(), "0,12,64,24,64,48,0000000000000000");
        assert_eq!(Placement::parse("0,12,64,24,64,48"), Some(p));
        let q = p.of_render(0xbeef_0000_0000_0001);
        assert_eq!(q.to_text(), "0,12,64,24,64,48,beef000000000001");
        assert_eq!(Placement::parse(&q.to_text()), Some(q));
        for bad in [
            "",
            "0,12,64,24,64",
            "0,12,64,24,64,48,x",
            "0,12,64,24,64,48,1,2",
            "0,12,65,24,64,48",
            "0,12,0,24,64,48",
            "a,1,2,3,4,5",
        ] {
            assert_eq!(Placement::parse(bad), None, "{bad}");
        }
        assert!(Placement::whole(3, 2).is_whole() && !p.is_whole());
    }

    #[test]
    fn alignment_holds_the_rectangle_within_the_frame() {
        let r = PixelRect { x0: 17, y0: 3, x1: 40, y1: 47 };
        assert_eq!(r.aligned_out(16, 64, 48), PixelRect { x0: 16, y0: 0, x1: 48, y1: 48 });
        assert_eq!(r.aligned_out(16, 45, 47), PixelRect { x0: 16, y0: 0, x1: 45, y1: 47 });
        assert_eq!(PixelRect::full(5, 5).aligned_out(0, 5, 5), PixelRect::full(5, 5));
        assert!(r.fits(40, 47) && !r.fits(39, 47) && !PixelRect { x0: 3, x1: 3, ..r }.fits(64, 64));
        let frame: Vec<usize> = (0..64 * 48).collect();
        let cut = r.cut(frame.clone(), 64);
        assert_eq!(cut.len(), r.len());
        assert_eq!(cut, r.frame_indices(64).collect::<Vec<_>>());
        assert_eq!(cut[r.index(20, 10)], 10 * 64 + 20);
        let empty = PixelRect { x0: 9, y0: 0, x1: 3, y1: 5 };
        assert!(empty.cut(frame.clone(), 64).is_empty() && empty.frame_indices(64).next().is_none());
        assert_eq!(PixelRect::full(64, 48).cut(frame.clone(), 64), frame);
    }
}
