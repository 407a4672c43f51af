//! `beam bench gpu`: the nonlinear renderer on the GPU (beam atlases and rays through wgpu, the
//! tree and the shading on the CPU) against the CPU renderer, measured in the same run on the
//! built-in nonlinear scenes; each GPU image checked against the CPU's.

use beam_cpu::nonlinear::{CpuBeams, Degree, NonlinearOptions, render_nonlinear_with};
use beam_cpu::render::{RenderOptions, difference};
use beam_gpu::Gpu;
use beam_gpu::nonlinear::GpuBeams;
use beam_scene::scene;
use std::time::Instant;

/// The built-in scenes of 000's figures.
pub const SCENES: [&str; 6] =
    ["mirror-teapot", "mirror-glass", "facing-mirrors", "glass-lens", "wavy-lake", "bumpy-mirror"];

/// Run the benchmark: `frames` timed GPU frames per scene (after one warm-up frame) and one CPU
/// frame, at `width × height`.
pub fn run(scenes: &[String], width: u32, height: u32, frames: u32, degree: Degree) -> Result<(), String> {
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    println!(
        "GPU: {}; {width}×{height}, {frames} timed frames per scene, {degree:?}, 2 tree levels, no area-light caustics",
        gpu.describe()
    );
    println!(
        "{:<16} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9} {:>8}",
        "scene", "GPU fps", "GPU ms", "atlas ms", "rays ms", "shade ms", "CPU ms", "CPU/GPU", "beams", "PSNR"
    );
    for name in scenes {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let options = NonlinearOptions {
            degree,
            texels: 32,
            bounces: 2,
            // Area lights' caustics are left out: they do not depend on the view, so an interactive
            // renderer makes them once per light, not per frame (point lights' are still traced).
            caustic_strata: 0,
            shading: RenderOptions::exact(width, height),
        };
        let renderer = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let (warm, _) = render_nonlinear_with(&scene, &options, &renderer).map_err(|e| e.to_string())?;
        let before = renderer.times();
        let start = Instant::now();
        let mut stats = None;
        for _ in 0..frames.max(1) {
            stats = Some(render_nonlinear_with(&scene, &options, &renderer).map_err(|e| e.to_string())?.1);
        }
        let per_frame = start.elapsed().as_secs_f64() / f64::from(frames.max(1));
        let after = renderer.times();
        let atlas = (after.atlas_seconds - before.atlas_seconds) / f64::from(frames.max(1));
        let rays = (after.ray_seconds - before.ray_seconds) / f64::from(frames.max(1));
        let shade = (after.shade_seconds - before.shade_seconds) / f64::from(frames.max(1));
        let start = Instant::now();
        let (cpu_image, _) = render_nonlinear_with(&scene, &options, &CpuBeams).map_err(|e| e.to_string())?;
        let cpu = start.elapsed().as_secs_f64();
        let psnr = difference(&warm, &cpu_image).map_err(|e| e.to_string())?.psnr;
        let beams: u64 = stats.map_or(0, |s| s.beams_per_level.iter().sum());
        println!(
            "{name:<16} {:>9.2} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>9.2} {beams:>9} {:>8}",
            1.0 / per_frame,
            1e3 * per_frame,
            1e3 * atlas,
            1e3 * rays,
            1e3 * shade,
            1e3 * cpu,
            cpu / per_frame,
            if psnr.is_finite() { format!("{psnr:.1}") } else { "equal".into() },
        );
    }
    println!(
        "GPU ms: whole frame (the beam tree's directions, culling and packing stay on the CPU); atlas ms: \
         beam visibility on the GPU (upload, bounding triangles, draws, hit readback); rays ms: the eye's rays \
         and the Whitted rays past the last tree level; shade ms: the GPU shading pass (area lights by 64 \
         shadow rays) and the composite, radiance kept on the GPU; PSNR: GPU image vs the CPU's (exact soft \
         shadows)."
    );
    Ok(())
}
