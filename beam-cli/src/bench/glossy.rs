//! `beam bench glossy`: glossy light volumes (002) against photon tracing at equal error, frame
//! against frame. The reference is a many-photon frame; the beam frame reads its scattered light
//! through the photon map's kernel ([`beam_cpu::glossy::PhotonKernel`]: the beams splatted into the
//! map's texels once a frame, each specular beam's flux integrated exactly over the tents), so the
//! two estimate the same image; photon frames of doubling photon counts are timed until one is as
//! close to the reference as the beam frame. Also timed: the unfiltered beam frame (one gather a
//! pixel) through the cone hierarchy, over every beam, and with the gather on the GPU.

use beam_cpu::glossy::{glossy_photons, photon_texel, render_glossy, render_glossy_photons};
use beam_cpu::render::difference;
use beam_render::BackendError;
use beam_render::glossy::{GlossyOptions, LightVolumes};
use beam_render::image::Image;
use beam_scene::scene;
use plotters::prelude::*;
use std::path::Path;
use std::time::Instant;

/// The three built-ins of 002's figures.
pub(crate) const SCENES: [&str; 3] = ["cardioid-ring", "pool-caustics", "stained-glass"];

/// One scene's measurements.
struct Measured {
    name: String,
    /// (seconds, RMSE) of the filtered beam frame.
    beams: (f64, f64),
    /// (photons, seconds, RMSE) per photon frame.
    photons: Vec<(u64, f64, f64)>,
}

/// Seconds of `f`'s second run (the first warms caches and pipelines), and its result.
fn timed<T, E: ToString>(mut f: impl FnMut() -> Result<T, E>) -> Result<(f64, T), String> {
    f().map_err(|e| e.to_string())?;
    let start = Instant::now();
    let out = f().map_err(|e| e.to_string())?;
    Ok((start.elapsed().as_secs_f64(), out))
}

/// Run the benchmark on `scenes` at `size²`, the reference with `reference` photons per light,
/// curved scatterers split `subdivide²`.
pub(crate) fn run(scenes: &[String], size: u32, reference: u64, subdivide: u32, out: &Path) -> Result<(), String> {
    let gpu = beam_gpu::Gpu::new().ok();
    println!(
        "{size}×{size}; reference {reference} photons per light; --subdivide {subdivide}; GPU: {}",
        gpu.as_ref().map_or_else(|| "none".to_string(), beam_gpu::Gpu::describe)
    );
    println!(
        "{:<15} {:>9} {:>8} {:>6} {:>11} {:>10} {:>9} {:>9} {:>9} {:>9}",
        "scene", "beams ms", "RMSE", "PSNR", "photons", "photon ms", "speed-up", "sharp ms", "linear ms", "GPU ms"
    );
    let mut all = Vec::new();
    for name in scenes {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let sharp = GlossyOptions { subdivide, ..GlossyOptions::new(size, size) };
        let truth: Image = render_glossy_photons(&scene, size, size, &glossy_photons(&scene, reference, 7))
            .map_err(|e| e.to_string())?;
        let options = GlossyOptions { filter: photon_texel(&scene), ..sharp };
        let (beam_seconds, (image, _)) = timed(|| render_glossy(&scene, &options))?;
        let d = difference(&image, &truth).map_err(|e| e.to_string())?;
        let mut photons = Vec::new();
        // Doubling up to half the reference's count.
        let mut n = (reference >> 14).max(1_000);
        let matched = loop {
            let (seconds, img) = timed(|| render_glossy_photons(&scene, size, size, &glossy_photons(&scene, n, 1)))?;
            let e = difference(&img, &truth).map_err(|e| e.to_string())?.rmse;
            photons.push((n, seconds, e));
            if e <= d.rmse {
                break Some((n, seconds));
            }
            if n * 2 > reference.div_ceil(2) {
                break None;
            }
            n *= 2;
        };
        let (count, ms, ratio) = match matched {
            Some((n, s)) => (n.to_string(), format!("{:.0}", 1e3 * s), format!("{:.1}×", s / beam_seconds)),
            None => {
                let last = photons.last().map_or(0.0, |p| p.1);
                (format!("> {n}"), format!("> {:.0}", 1e3 * last), format!("> {:.1}×", last / beam_seconds))
            }
        };
        let (sharp_seconds, _) = timed(|| render_glossy(&scene, &sharp))?;
        let (linear_seconds, _) = timed(|| render_glossy(&scene, &GlossyOptions { hierarchy: false, ..sharp }))?;
        let gpu_ms = match &gpu {
            Some(g) => Some(gpu_frame(g, &scene, &sharp)?),
            None => None,
        };
        println!(
            "{name:<15} {:>9.0} {:>8.5} {:>6.1} {count:>11} {ms:>10} {ratio:>9} {:>9.0} {:>9.0} {:>9}",
            1e3 * beam_seconds,
            d.rmse,
            d.psnr,
            1e3 * sharp_seconds,
            1e3 * linear_seconds,
            gpu_ms.map_or_else(|| "-".into(), |m| format!("{m:.0}")),
        );
        all.push(Measured { name: name.clone(), beams: (beam_seconds, d.rmse), photons });
    }
    println!(
        "beams ms: the beam frame on the CPU with its scattered light read through the photon map's kernel \
         (light volumes, cone hierarchy, the scattered beams splatted into the map's texels, shadow beams per pixel, eye rays, direct light); RMSE, PSNR: \
         against the reference frame (sRGB); photons: the fewest photons per light (doubling up to half the reference's) \
         whose frame is as close, and its ms (photon tracing, the same eye rays and direct light); speed-up: \
         photon ms over beam ms; sharp ms: the unfiltered beam frame (one gather a pixel); linear ms: that \
         with the gather over every beam (002); GPU ms: that with the gather on the GPU."
    );
    plot(out, &all)?;
    println!("plot -> {}", out.display());
    Ok(())
}

/// Milliseconds of a glossy frame with the gather on the GPU.
fn gpu_frame(gpu: &beam_gpu::Gpu, scene: &scene::Scene, options: &GlossyOptions) -> Result<f64, String> {
    let gather = beam_gpu::glossy::GpuGather::new(gpu, scene).map_err(|e| e.to_string())?;
    let run = |v: &LightVolumes, points: &[(beam_math::glam::Vec3, beam_math::glam::Vec3)]| {
        gather.gather(gpu, v, points, options).map_err(BackendError::from)
    };
    beam_cpu::glossy::render_glossy_with(scene, options, &beam_cpu::nonlinear::CpuBeams, &run)
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    beam_cpu::glossy::render_glossy_with(scene, options, &beam_cpu::nonlinear::CpuBeams, &run)
        .map_err(|e| e.to_string())?;
    Ok(1e3 * start.elapsed().as_secs_f64())
}

/// RMSE against time: each scene's photon renders as a line, its beam render as a dot.
fn plot(path: &Path, all: &[Measured]) -> Result<(), String> {
    crate::plot::png(path, (600 * all.len().max(1) as u32, 520), |root| {
        for (panel, m) in root.split_evenly((1, all.len().max(1))).iter().zip(all) {
            let times = m.photons.iter().map(|p| p.1).chain([m.beams.0]);
            let errors = m.photons.iter().map(|p| p.2).chain([m.beams.1]);
            let (t0, t1) = times.fold((f64::INFINITY, 0.0f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
            let (e0, e1) = errors.fold((f64::INFINITY, 0.0f64), |(lo, hi), e| (lo.min(e), hi.max(e)));
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{}: RMSE vs time", m.name), ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(
                    (t0.max(1e-4) * 0.7..t1 * 1.4).log_scale(),
                    (e0.max(1e-5) * 0.7..e1 * 1.4).log_scale(),
                )
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc("seconds")
                .y_desc("RMSE (sRGB)")
                .x_label_formatter(&|v| format!("{v:.3}"))
                .y_label_formatter(&|v| format!("{v:.3}"))
                .draw()
                .map_err(|e| e.to_string())?;
            let series = [
                ("photon tracing", BLUE, m.photons.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>()),
                ("light volumes (beams)", RED, vec![m.beams]),
            ];
            crate::plot::lines(&mut chart, series.into())?;
        }
        Ok(())
    })
}
