//! One row of `beam bench softshadow --suite` / `--sweep light`: every method on one scene in one
//! process, timed `runs` times (medians), each image against a reference of the same pixels.
//!
//! Shadow rays are counted per pixel over all lights, as a ray tracer's samples per pixel are: with
//! `n` lights, "256 rays" is `max(1, round(256 / n))` rays to each (the renderer's `spp` is per
//! light). Two references of `--reference-spp` rays per pixel each: the pixel centres' (for every
//! method that traces primary rays through pixel centres) and the box-filtered pixels' (for eye
//! beams, whose coverage is exact over the pixel): `s × s` pixel centres per pixel (`s` up to 8),
//! averaged, with the rays shared among them.

use super::softshadow::options;
use beam_cpu::render::{RenderStats, difference, render};
use beam_math::glam::Vec3;
use beam_render::image::Image;
use beam_render::options::Method;
use beam_scene::scene::Scene;

/// The methods, in table order: eye beams + shadow beams (`beam render`'s default), shadow beams
/// from primary rays at pixel centres, our rays at 64 and 256 per pixel, Embree's at 256.
pub(super) const METHODS: [&str; 5] = ["beam", "beam, primary rays", "rays 64", "rays 256", "embree 256"];

/// One scene's measurements.
pub(super) struct Row {
    /// Case name.
    pub case: String,
    /// The light's edge as a fraction of the scene's extent (light sweep rows).
    pub light: Option<f32>,
    /// Triangles.
    pub triangles: usize,
    /// Lights.
    pub lights: usize,
    /// Shadow rays to each light of rays 64, rays 256 and the references.
    pub rays_per_light: [u32; 3],
    /// Median seconds of each of [`METHODS`] (`None`: Embree in a build without `peers`).
    pub seconds: [Option<f64>; 5],
    /// RMSE of each against its reference: the box-filtered one for eye beams, else the pixel
    /// centres'.
    pub rmse: [Option<f64>; 5],
    /// RMSE of the eye beams' image against the pixel centres' reference.
    pub rmse_beam_centres: f64,
    /// Miss pieces of the shadow-beam splits per pixel (beams from primary rays).
    pub pieces_per_pixel: f64,
    /// Hit beams per pixel (beams from primary rays).
    pub hit_beams_per_pixel: f64,
    /// Shadow beams traced (beams from primary rays).
    pub shadow_beams: u64,
    /// Share of the pixels whose shadow beams were all exact (beams from primary rays; the others
    /// ran past their budget and sampled the rest of their light).
    pub exact_share: f64,
}

impl Row {
    /// The bar: shadow beams no slower than our 256 rays from the same primary rays (001 §5.1's
    /// comparison), with an RMSE no larger.
    #[must_use]
    pub(super) fn pass(&self) -> bool {
        match (self.seconds[1], self.seconds[3], self.rmse[1], self.rmse[3]) {
            (Some(t), Some(t256), Some(e), Some(e256)) => t <= t256 && e <= e256,
            _ => false,
        }
    }
}

/// The images a row may write: eye beams, beams from primary rays, rays 256 and the pixel centres'
/// reference.
pub(super) struct Images {
    /// Eye beams + shadow beams.
    pub beam: Image,
    /// Shadow beams from the rays' primary rays (what the bar judges).
    pub beam_rays: Image,
    /// Our 256 rays.
    pub rays: Image,
    /// The pixel centres' reference.
    pub reference: Image,
}

/// Shadow rays to each of `lights` lights for `per_pixel` rays per pixel in all.
#[must_use]
pub(super) fn rays_per_light(per_pixel: u32, lights: usize) -> u32 {
    let n = lights.max(1) as u32;
    ((per_pixel + n / 2) / n).max(1)
}

/// Supersampling of the box-filtered reference: the largest `s` of 8, 4, 2, 1 with `s²` at most
/// the reference's rays per light and an image side `s × size` of at most 4096.
fn supersampling(per_light: u32, size: u32) -> u32 {
    [8, 4, 2, 1].into_iter().find(|&s| s * s <= per_light && s * size <= 4096).unwrap_or(1)
}

/// The mean of each `s × s` block of `img`.
fn downsample(img: &Image, s: u32) -> Image {
    let mut out = Image::new(img.width / s, img.height / s);
    for y in 0..out.height {
        for x in 0..out.width {
            let mut sum = Vec3::ZERO;
            for j in 0..s {
                for i in 0..s {
                    sum += img.pixels[((y * s + j) * img.width + x * s + i) as usize];
                }
            }
            out.pixels[(y * out.width + x) as usize] = sum / (s * s) as f32;
        }
    }
    out
}

/// The middle value of `v`.
fn median(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| super::stats::median(v.to_vec()))
}

/// Every method on `scene` at `size × size`, `runs` times in turn (so that a slow spell of the
/// machine falls on all of them), against references of `reference_spp` rays per pixel.
pub(super) fn measure(
    scene: &Scene,
    case: &str,
    light: Option<f32>,
    size: u32,
    runs: u32,
    reference_spp: u32,
) -> Result<(Row, Images), String> {
    let n = scene.lights.len();
    let per = [64, 256, reference_spp].map(|spp| rays_per_light(spp, n));
    let s = supersampling(per[2], size);
    let bar = crate::progress::bar(u64::from(size) * u64::from(1 + s + 5 * runs), "");
    bar.set_message(match light {
        Some(f) => format!("{case}, light {f}"),
        None => case.to_string(),
    });
    let (reference, _) = render(scene, &options(size, Method::Ray, per[2], 99, false), || bar.inc(1));
    let (fine, _) = render(scene, &options(size * s, Method::Ray, (per[2] / (s * s)).max(1), 99, false), || {
        bar.inc(1);
    });
    let boxed = downsample(&fine, s);
    #[cfg(feature = "peers")]
    let embree = Some(super::peers::embree_occluder(&scene.triangles)?);
    #[cfg(not(feature = "peers"))]
    let embree: Option<Box<beam_render::queries::AnyHit<'static>>> = None;
    let mut seconds: [Vec<f64>; 5] = Default::default();
    let mut images: [Option<Image>; 5] = Default::default();
    let mut beam_stats: Option<RenderStats> = None;
    for _ in 0..runs {
        for (m, (method, spp, eye)) in [
            // The beams' `--spp` (their budget, and the rays of what they sample) as rays 256's.
            (Method::Beam, per[1], true),
            (Method::Beam, per[1], false),
            (Method::Ray, per[0], false),
            (Method::Ray, per[1], false),
        ]
        .into_iter()
        .enumerate()
        {
            let (img, st) = render(scene, &options(size, method, spp, 1, eye), || bar.inc(1));
            seconds[m].push(st.seconds);
            images[m].get_or_insert(img);
            if m == 1 {
                beam_stats.get_or_insert(st);
            }
        }
        match &embree {
            Some(e) => {
                let (img, st) =
                    beam_cpu::render::render_with(scene, &options(size, Method::Ray, per[1], 1, false), &**e, || {
                        bar.inc(1);
                    });
                seconds[4].push(st.seconds);
                images[4].get_or_insert(img);
            }
            None => bar.inc(u64::from(size)),
        }
    }
    bar.finish_and_clear();
    let rmse = |m: usize, reference: &Image| -> Result<Option<f64>, String> {
        images[m].as_ref().map(|img| difference(img, reference).map(|d| d.rmse)).transpose().map_err(|e| e.to_string())
    };
    let bs = beam_stats.ok_or("no beam run")?;
    let pixels = f64::from(size) * f64::from(size);
    let row = Row {
        case: case.to_string(),
        light,
        triangles: scene.stats.triangles,
        lights: n,
        rays_per_light: per,
        seconds: seconds.each_ref().map(|v| median(v)),
        rmse: [
            rmse(0, &boxed)?,
            rmse(1, &reference)?,
            rmse(2, &reference)?,
            rmse(3, &reference)?,
            rmse(4, &reference)?,
        ],
        rmse_beam_centres: rmse(0, &reference)?.unwrap_or(f64::NAN),
        pieces_per_pixel: bs.pieces as f64 / pixels,
        hit_beams_per_pixel: bs.hit_beams_per_pixel,
        shadow_beams: bs.shadow_beams,
        exact_share: bs.exact_pixel_share,
    };
    let [beam, beam_rays, _, rays, _] = images;
    let beam_rays = beam_rays.ok_or("no image of beams from primary rays")?;
    Ok((row, Images { beam: beam.ok_or("no beam image")?, beam_rays, rays: rays.ok_or("no ray image")?, reference }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_are_shared_among_lights() {
        assert_eq!(rays_per_light(256, 1), 256);
        assert_eq!(rays_per_light(256, 36), 7);
        assert_eq!(rays_per_light(64, 256), 1);
        assert_eq!(rays_per_light(4096, 256), 16);
        assert_eq!(supersampling(4096, 256), 8);
        assert_eq!(supersampling(16, 256), 4);
        assert_eq!(supersampling(4096, 1024), 4);
    }

    #[test]
    fn downsampling_averages_blocks() {
        let mut img = Image::new(4, 2);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            *p = Vec3::splat(i as f32);
        }
        let d = downsample(&img, 2);
        assert_eq!((d.width, d.height), (2, 1));
        assert_eq!(d.pixels, vec![Vec3::splat(2.5), Vec3::splat(4.5)]);
    }
}
