//! `beam bench primary --backend gpu`: primary visibility by the GPU's compute ray tracer
//! ([`GpuQueries`]' closest hits) on the same stratified jittered rays (1, 4 and 16 per pixel) and
//! the same flat image as the CPU's rays of [`super::primary`], measured in the same run: the
//! device's own time by timestamp queries, the host's wall time, rays per second, and the PSNR of
//! each GPU image against the CPU rays' image of the same rays.

use super::primary_shading::flat;
use beam_cpu::render::{difference, pixel_samples};
use beam_gpu::Gpu;
use beam_gpu::queries::GpuQueries;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::image::Image;
use beam_render::queries::RayQueries;
use beam_scene::scene::{Camera, Scene};
use rayon::prelude::*;
use std::time::Instant;

/// Most rays a batch sends to the device (as the host-driven frames batch them).
const MAX_BATCH: usize = 1 << 20;

/// One GPU image of `spp` rays per pixel.
pub(super) struct GpuRays {
    /// Rays per pixel.
    pub spp: u32,
    /// The flat image.
    pub image: Image,
    /// Wall time of the image on the host: rays made, traced on the device, read back, shaded.
    pub host_seconds: f64,
    /// The device's own time in the ray dispatches (timestamp queries; `None` without them).
    pub gpu_seconds: Option<f64>,
    /// Rays traced.
    pub rays: u64,
}

/// [`super::primary::ray_image`] with the closest hits from `queries` (timed, [`GpuQueries::timed`]):
/// bands of whole rows of at most [`MAX_BATCH`] rays each (one row at least); `row_done` after
/// each band's rows.
pub(super) fn ray_image(
    scene: &Scene,
    camera: &Camera,
    spp: u32,
    queries: &GpuQueries<'_>,
    row_done: &(dyn Fn() + Sync),
) -> Result<GpuRays, String> {
    let start = Instant::now();
    queries.take_times();
    let shade = flat(scene);
    let frame = camera.frame();
    let k = ((spp.max(1) as f32).sqrt() as u32).max(1);
    let per_row = camera.width as usize * (k * k) as usize;
    let rows = (MAX_BATCH / per_row.max(1)).max(1);
    let mut image = Image::new(camera.width, camera.height);
    for (band, pixels) in image.pixels.chunks_mut(rows * camera.width as usize).enumerate() {
        let y0 = band * rows;
        let width = camera.width as usize;
        let rays: Vec<Ray> = (0..pixels.len())
            .into_par_iter()
            .flat_map_iter(|i| {
                let (x, y) = (i % width, y0 + i / width);
                pixel_samples(x as u32, y as u32, k).map(|(sx, sy)| camera.ray(&frame, sx, sy)).collect::<Vec<_>>()
            })
            .collect();
        let hits = queries.closest_hits(scene, &rays).map_err(|e| e.to_string())?;
        let per_pixel = (k * k) as usize;
        pixels.par_iter_mut().enumerate().for_each(|(i, px)| {
            let samples = i * per_pixel..(i + 1) * per_pixel;
            let sum: Vec3 = (rays[samples.clone()].iter().zip(&hits[samples]))
                .filter_map(|(ray, hit)| {
                    hit.map(|h| shade(h.prim, ray.origin + h.t * ray.direction, ray.direction.normalize()))
                })
                .sum();
            *px = sum / per_pixel as f32;
        });
        (0..pixels.len() / width).for_each(|_| row_done());
    }
    let times = queries.take_times().unwrap_or_default();
    let rays = u64::from(camera.width) * u64::from(camera.height) * u64::from(k * k);
    Ok(GpuRays { spp, image, host_seconds: start.elapsed().as_secs_f64(), gpu_seconds: times.ray_seconds, rays })
}

/// The GPU images of 1, 4 and 16 rays per pixel of `scene` seen by `camera`, after an untimed
/// warm-up image of 1 (the device's first dispatches page in its memory).
pub(super) fn images(gpu: &Gpu, scene: &Scene, camera: &Camera) -> Result<Vec<GpuRays>, String> {
    let queries = GpuQueries::new(gpu, scene).map(GpuQueries::timed).map_err(|e| e.to_string())?;
    ray_image(scene, camera, 1, &queries, &|| {})?;
    let mut out = Vec::new();
    for spp in [1, 4, 16] {
        let bar = crate::progress::bar(u64::from(camera.height), "GPU primary rays");
        out.push(ray_image(scene, camera, spp, &queries, &|| bar.inc(1))?);
        bar.finish_and_clear();
    }
    Ok(out)
}

/// The GPU table: each of `runs` against `cpu`, the CPU rays' (image, seconds) of the same rays per
/// pixel.
pub(super) fn print_table(gpu: &Gpu, runs: &[GpuRays], cpu: &[(u32, &Image, f64)]) -> Result<(), String> {
    println!(
        "\nGPU: {}\n{:<18} {:>9} {:>9} {:>11} {:>12} {:>9} {:>9} {:>14}",
        gpu.describe(),
        "method",
        "GPU ms",
        "host ms",
        "Mrays/s GPU",
        "Mrays/s host",
        "CPU ms",
        "CPU/GPU",
        "PSNR vs CPU dB"
    );
    for r in runs {
        let Some(&(_, cpu_image, cpu_seconds)) = cpu.iter().find(|(spp, _, _)| *spp == r.spp) else { continue };
        let psnr = difference(&r.image, cpu_image).map_err(|e| e.to_string())?.psnr;
        let mrays = |s: f64| r.rays as f64 / s / 1e6;
        println!(
            "{:<18} {:>9} {:>9.1} {:>11} {:>12.2} {:>9.1} {:>9.2} {:>14}",
            format!("gpu rays {} spp", r.spp),
            r.gpu_seconds.map_or_else(|| "n/a".into(), |s| format!("{:.1}", 1e3 * s)),
            1e3 * r.host_seconds,
            r.gpu_seconds.map_or_else(|| "n/a".into(), |s| format!("{:.2}", mrays(s))),
            mrays(r.host_seconds),
            1e3 * cpu_seconds,
            cpu_seconds / r.host_seconds,
            if psnr.is_finite() { format!("{psnr:.1}") } else { "equal".into() },
        );
    }
    println!(
        "GPU ms: the device's own time in the ray dispatches (timestamp queries; n/a where the device has none); \
         host ms: wall time of the GPU image (rays made, traced, read back and shaded on the host); CPU ms: our \
         rays on the CPU, the same rays; CPU/GPU: CPU ms / host ms; PSNR: GPU image vs the CPU rays' image."
    );
    Ok(())
}
