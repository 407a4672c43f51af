//! How far apart two images of one render are.

/// How two images of one render differ, in sRGB: pixels whose largest channel differs by more
/// than 4/255, the sum of those largest differences, and the pixel count.
pub(crate) struct PixelDifference {
    pub differ: u64,
    pub sum: f64,
    pub n: u64,
}

impl PixelDifference {
    pub(crate) fn of(a: &beam_render::image::Image, b: &beam_render::image::Image) -> Self {
        let (mut differ, mut sum) = (0u64, 0.0f64);
        for (a, b) in a.pixels.iter().zip(&b.pixels) {
            let d = (0..3)
                .map(|k| (beam_render::image::srgb_encode(a[k]) - beam_render::image::srgb_encode(b[k])).abs())
                .fold(0.0f32, f32::max);
            sum += f64::from(d);
            differ += u64::from(d > 4.0 / 255.0);
        }
        Self { differ, sum, n: a.pixels.len() as u64 }
    }
}
