//! `beam bench glossy`: glossy light volumes (002) against photon tracing at equal error. Per
//! built-in: a many-photon reference image; the beam render's time and RMSE against it (gather
//! through the cone hierarchy and linearly, on the CPU and, when an adapter exists, the GPU); then
//! photon renders of doubling photon counts, each timed and compared with the reference, until one
//! reaches the beams' RMSE. Prints the ratio of the times and plots RMSE against time.

use beam_cpu::glossy::{GlossyOptions, LightVolumes, glossy_photons, render_glossy, render_glossy_photons};
use beam_cpu::render::{Image, difference};
use beam_cpu::scene;
use plotters::prelude::*;
use std::path::Path;
use std::time::Instant;

/// The three built-ins of 002's figures.
pub const SCENES: [&str; 3] = ["cardioid-ring", "pool-caustics", "stained-glass"];

/// One scene's measurements.
struct Measured {
    name: String,
    /// (seconds, RMSE) of the beam render.
    beams: (f64, f64),
    /// (photons, seconds, RMSE) per photon render.
    photons: Vec<(u64, f64, f64)>,
}

/// Run the benchmark on `scenes` at `size²`, the reference with `reference` photons per light.
pub fn run(scenes: &[String], size: u32, reference: u64, out: &Path) -> Result<(), String> {
    let gpu = beam_gpu::Gpu::new().ok();
    println!(
        "{size}×{size}; reference {reference} photons per light; GPU: {}",
        gpu.as_ref().map_or_else(|| "none".to_string(), beam_gpu::Gpu::describe)
    );
    println!(
        "{:<15} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9} {:>12} {:>10} {:>8}",
        "scene", "beams", "gather", "linear", "GPU", "RMSE", "PSNR", "photons", "photon ms", "speed-up"
    );
    let mut all = Vec::new();
    for name in scenes {
        let scene = scene::builtin(name)?;
        let reference_image = render_glossy_photons(&scene, size, size, &glossy_photons(&scene, reference, 7))?;
        let options = GlossyOptions::new(size, size);
        // Warm, then time the frame.
        render_glossy(&scene, &options)?;
        let start = Instant::now();
        let (image, stats) = render_glossy(&scene, &options)?;
        let beam_seconds = start.elapsed().as_secs_f64();
        let (_, linear) = render_glossy(&scene, &GlossyOptions { hierarchy: false, ..options })?;
        let gpu_ms = match &gpu {
            Some(g) => Some(gpu_frame(g, &scene, &options)?),
            None => None,
        };
        let rmse = difference(&image, &reference_image)?.rmse;
        let psnr = difference(&image, &reference_image)?.psnr;
        let mut photons = Vec::new();
        let mut n = 62_500u64;
        let matched = loop {
            let start = Instant::now();
            let img: Image = render_glossy_photons(&scene, size, size, &glossy_photons(&scene, n, 1))?;
            let seconds = start.elapsed().as_secs_f64();
            let e = difference(&img, &reference_image)?.rmse;
            photons.push((n, seconds, e));
            if e <= rmse {
                break Some((n, seconds));
            }
            if n * 2 > reference / 2 {
                break None;
            }
            n *= 2;
        };
        let (count, ms, ratio) = match matched {
            Some((n, s)) => (n.to_string(), format!("{:.1}", 1e3 * s), format!("{:.1}×", s / beam_seconds)),
            None => {
                let last = photons.last().map_or(0.0, |p| p.1);
                (format!("> {}", n), format!("> {:.1}", 1e3 * last), format!("> {:.1}×", last / beam_seconds))
            }
        };
        println!(
            "{name:<15} {:>8.1} {:>8.1} {:>9.1} {:>9} {:>9.5} {:>9.1} {count:>12} {ms:>10} {ratio:>8}",
            1e3 * beam_seconds,
            1e3 * stats.gather_seconds,
            1e3 * linear.gather_seconds,
            gpu_ms.map_or_else(|| "-".into(), |m| format!("{m:.1}")),
            rmse,
            psnr,
        );
        all.push(Measured { name: name.clone(), beams: (beam_seconds, rmse), photons });
    }
    println!(
        "beams: whole frame ms on the CPU (beams, eye rays, gather through the cone hierarchy, direct light); \
         gather: its gather ms; linear: the gather over every beam (002); GPU: frame ms with the gather on the \
         GPU; RMSE/PSNR: against the reference (sRGB); photons: the fewest photons per light (doubling from \
         62,500) whose render reaches the beams' RMSE, and its ms (photon tracing and the same eye pass); \
         speed-up: photon ms over beam ms."
    );
    plot(out, &all)?;
    println!("plot -> {}", out.display());
    Ok(())
}

/// Milliseconds of a glossy frame with the gather on the GPU.
fn gpu_frame(gpu: &beam_gpu::Gpu, scene: &scene::Scene, options: &GlossyOptions) -> Result<f64, String> {
    let gather = beam_gpu::glossy::GpuGather::new(gpu, scene)?;
    let run = |v: &LightVolumes, points: &[(beam_math::glam::Vec3, beam_math::glam::Vec3)]| {
        gather.gather(gpu, v, points, options)
    };
    beam_cpu::glossy::render_glossy_with(scene, options, &beam_cpu::nonlinear::CpuBeams, &run)?;
    let start = Instant::now();
    beam_cpu::glossy::render_glossy_with(scene, options, &beam_cpu::nonlinear::CpuBeams, &run)?;
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
            chart.configure_mesh().x_desc("seconds").y_desc("RMSE (sRGB)").draw().map_err(|e| e.to_string())?;
            let series = [
                ("photon tracing", BLUE, m.photons.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>()),
                ("light volumes (beams)", RED, vec![m.beams]),
            ];
            crate::plot::lines(&mut chart, series.into())?;
        }
        Ok(())
    })
}
