//! `beam bench softshadow --backend gpu`: exact soft shadows on the GPU — the host-driven frame of
//! `beam render --backend gpu --method beam` ([`render_queries`] over [`GpuQueries`]: primary rays
//! at pixel centres, every shadow beam traced to the end on the device, those past its limits on
//! the host) — against the CPU's exact soft shadows measured in the same run: the device's time
//! in the shadow-beam dispatches by timestamp queries, the host's wall time, beams per second,
//! overflow beams, loop iterations per beam, CPU/GPU and the PSNR of the GPU image against the
//! CPU's. The GPU reports no pieces per beam (its shader counts loop iterations, not pieces).

use super::stats::median;
use beam_cpu::render::{difference, render_queries};
use beam_gpu::Gpu;
use beam_gpu::queries::GpuQueries;
use beam_gpu::shadow_beam::Walk;
use beam_render::image::Image;
use beam_render::options::RenderOptions;
use beam_scene::scene::Scene;
use std::time::Instant;

/// The GPU frame of one scene, `runs` times (after a warm-up frame).
pub(super) struct GpuRun {
    /// The first timed run's image.
    pub image: Image,
    /// Median wall time of the frame on the host (`render_queries`: rays and beams on the device,
    /// the frame's host work and its waits), seconds.
    pub host_seconds: f64,
    /// Median of the device's own time in the shadow-beam dispatches (`None` without timestamp
    /// queries), seconds.
    pub beam_seconds: Option<f64>,
    /// Median of the device's own time in the ray dispatches (camera rays, and any shadow rays of
    /// point lights or the environment), seconds.
    pub ray_seconds: Option<f64>,
    /// Shadow beams of a frame (one per shade point and area light).
    pub beams: u64,
    /// Of them, those the device gave up on past its limits, traced on the host.
    pub overflow: u64,
    /// Loop iterations the device's shadow beams ran in a frame.
    pub iterations: u64,
    /// Seconds to upload the BVH and compile the pipelines (once per scene, not in the frames).
    pub setup_seconds: f64,
}

/// Render `scene` with `options` (method `beam`) on `gpu` by [`render_queries`], the shadow beams
/// walking the BVH as `walk` says, `runs` times (at least once) after an untimed warm-up frame (the
/// device's first dispatches page in its memory); `row_done` after each image row of each timed run.
pub(super) fn run(
    gpu: &Gpu,
    scene: &Scene,
    (options, walk): (&RenderOptions, Walk),
    runs: u32,
    row_done: &(dyn Fn() + Sync),
) -> Result<GpuRun, String> {
    let start = Instant::now();
    let queries =
        GpuQueries::new(gpu, scene).and_then(|q| q.walking(walk)).map(GpuQueries::timed).map_err(|e| e.to_string())?;
    let setup_seconds = start.elapsed().as_secs_f64();
    let (mut host, mut beam, mut ray) = (Vec::new(), Vec::new(), Vec::new());
    let mut first = None;
    render_queries(scene, options, &queries, || {}).map_err(|e| e.to_string())?;
    for _ in 0..runs.max(1) {
        queries.take_times();
        let start = Instant::now();
        let (image, stats) = render_queries(scene, options, &queries, row_done).map_err(|e| e.to_string())?;
        host.push(start.elapsed().as_secs_f64());
        let times = queries.take_times().unwrap_or_default();
        beam.extend(times.beam_seconds);
        ray.extend(times.ray_seconds);
        first.get_or_insert((image, stats, times));
    }
    let (image, stats, times) = first.ok_or("no GPU run")?;
    let some_median = |v: Vec<f64>| (!v.is_empty()).then(|| median(v));
    Ok(GpuRun {
        image,
        host_seconds: median(host),
        beam_seconds: some_median(beam),
        ray_seconds: some_median(ray),
        beams: stats.shadow_beams,
        overflow: stats.overflow_beams,
        iterations: times.beam_iterations,
        setup_seconds,
    })
}

/// A GPU row against the CPU's exact soft shadows of the same pixels.
pub(super) struct Compared {
    /// Scene (and light size of a sweep row).
    pub name: String,
    /// The GPU's frame.
    pub gpu: GpuRun,
    /// The CPU's seconds.
    pub cpu_seconds: f64,
    /// PSNR of the GPU image against the CPU's, dB (infinite for equal images).
    pub psnr: f64,
    /// RMSE of the GPU image against the many-ray reference.
    pub rmse: f64,
}

impl Compared {
    /// `run` on `name` against the CPU's `cpu` image of `cpu_seconds`, and the `reference`.
    pub(super) fn new(
        name: String,
        gpu: GpuRun,
        (cpu, cpu_seconds): (&Image, f64),
        reference: &Image,
    ) -> Result<Self, String> {
        let psnr = difference(&gpu.image, cpu).map_err(|e| e.to_string())?.psnr;
        let rmse = difference(&gpu.image, reference).map_err(|e| e.to_string())?.rmse;
        Ok(Self { name, gpu, cpu_seconds, psnr, rmse })
    }
}

/// The GPU table's header: the device, then the column names.
#[must_use]
pub(super) fn header(gpu: &Gpu) -> String {
    format!(
        "GPU: {}\n{:<18} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9} {:>9} {:>9} {:>8} {:>9}",
        gpu.describe(),
        "scene",
        "GPU ms",
        "rays ms",
        "host ms",
        "beams",
        "Mbeam/s G",
        "Mbeam/s h",
        "overflow",
        "iter/beam",
        "CPU ms",
        "CPU/GPU",
        "PSNR dB",
        "RMSE"
    )
}

/// One row of the GPU table.
#[must_use]
pub(super) fn line(c: &Compared) -> String {
    let g = &c.gpu;
    let ms = |s: Option<f64>| s.map_or_else(|| "n/a".to_string(), |s| format!("{:.1}", 1e3 * s));
    let per_second = |s: f64| g.beams as f64 / s / 1e6;
    format!(
        "{:<18} {:>9} {:>9} {:>9.1} {:>9} {:>10} {:>10.3} {:>9} {:>9.1} {:>9.1} {:>9.2} {:>8} {:>9.5}",
        c.name,
        ms(g.beam_seconds),
        ms(g.ray_seconds),
        1e3 * g.host_seconds,
        g.beams,
        g.beam_seconds.map_or_else(|| "n/a".to_string(), |s| format!("{:.3}", per_second(s))),
        per_second(g.host_seconds),
        g.overflow,
        g.iterations as f64 / g.beams.max(1) as f64,
        1e3 * c.cpu_seconds,
        c.cpu_seconds / g.host_seconds,
        if c.psnr.is_finite() { format!("{:.1}", c.psnr) } else { "equal".into() },
        c.rmse,
    )
}

/// What the GPU table's columns are.
pub(super) const FOOTNOTE: &str = "GPU ms: the device's own time in the shadow-beam dispatches, summed (timestamp \
     queries; n/a where the device has none); rays ms: likewise in the ray dispatches (camera rays); host ms: wall \
     time of the GPU frame after a warm-up frame (render_queries: primary rays, every shadow beam exact, those past \
     the device's limits traced on the host: overflow); Mbeam/s G and h: shadow beams per second of GPU ms and of \
     host ms (pieces per second: the device does not count pieces); iter/beam: the shader's loop iterations per \
     beam; CPU ms: the CPU's exact soft shadows (render with exact: true) from the same primary rays, measured in \
     the same run; CPU/GPU: CPU ms / host ms; PSNR: GPU image vs the CPU's; RMSE: GPU image vs the many-ray \
     reference. Times are medians of --runs in the suite.";

/// Every row, one line each (seconds; empty fields for what was not measured).
#[must_use]
pub(super) fn csv(rows: &[Compared]) -> String {
    let mut out = String::from(
        "scene,gpu_beam_s,gpu_ray_s,host_s,setup_s,shadow_beams,overflow_beams,beam_iterations,cpu_s,cpu_over_gpu,\
         psnr_vs_cpu,rmse_vs_reference\n",
    );
    let opt = |v: Option<f64>| v.map_or_else(String::new, |v| v.to_string());
    for c in rows {
        let g = &c.gpu;
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{}\n",
            c.name,
            opt(g.beam_seconds),
            opt(g.ray_seconds),
            g.host_seconds,
            g.setup_seconds,
            g.beams,
            g.overflow,
            g.iterations,
            c.cpu_seconds,
            c.cpu_seconds / g.host_seconds,
            c.psnr,
            c.rmse,
        ));
    }
    out
}
