//! `beam bench gpu`: the nonlinear renderer on the GPU (beam atlases and rays through wgpu, the
//! tree and the shading on the CPU) against the CPU renderer, measured in the same run on the
//! built-in nonlinear scenes; each GPU image checked against the CPU's.

use super::stats::median;
use beam_cpu::nonlinear::CpuBeams;
use beam_cpu::render::difference;
use beam_gpu::Gpu;
use beam_gpu::nonlinear::{GpuBeams, GpuFrame};
use beam_render::cpu_clock::our_threads_cpu_seconds;
use beam_render::image::Image;
use beam_render::nonlinear::Degree;
use beam_render::nonlinear::{
    FrameImage, NonlinearOptions, NonlinearPrecomputed, render_nonlinear_frame, render_nonlinear_with,
};
use beam_render::options::RenderOptions;
use beam_scene::scene::{self, Simplify};
use std::time::Instant;

/// The built-in scenes of 000's figures.
pub(crate) const SCENES: [&str; 6] =
    ["mirror-teapot", "mirror-glass", "facing-mirrors", "glass-lens", "wavy-lake", "bumpy-mirror"];

/// Run the benchmark: `frames` timed GPU frames per scene (after one warm-up frame) and one CPU
/// frame, at `width × height`; with `smesh`, beams spawn from coarse S meshes simplified so; with
/// `rasterize`, the atlas's nearest hits by draws even where compute could find them; with
/// `read_back`, every hit the host could use read back ([`GpuBeams::reading_levels_back`]); with
/// `read_image`, every timed frame's image read back (else kept on the GPU for display,
/// [`GpuBeams::displaying`]); with `moving`, the eye moved before every timed frame (no beam reused
/// from the frame before).
pub(crate) fn run(
    scenes: &[String],
    (width, height): (u32, u32),
    frames: u32,
    degree: Degree,
    smesh: Option<Simplify>,
    (rasterize, read_back, read_image, moving): (bool, bool, bool, bool),
) -> Result<(), String> {
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    let mut coarse = smesh.map_or_else(String::new, |s| format!(", coarse S meshes ({s:?})"));
    if read_back {
        coarse.push_str(", every hit the host could use read back");
    }
    coarse.push_str(if read_image {
        ", every frame's image read back"
    } else {
        ", every frame kept on the GPU for display (the warm-up frame's image read back for the PSNR)"
    });
    if moving {
        coarse.push_str(", the eye moved before every timed frame");
    }
    let hits = if GpuBeams::can_compute(&gpu) && !rasterize {
        "nearest hits by compute (64-bit atomics)"
    } else {
        "nearest hits by draws"
    };
    println!(
        "GPU: {}; {width}×{height}, {frames} timed frames per scene, {degree:?}, 2 tree levels, no area-light caustics \
         (the S mesh and point lights' caustics made once for the frames), {hits}{coarse}",
        gpu.describe()
    );
    println!(
        "{:<16} {:>9} {:>10} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9} {:>13} {:>8}",
        "scene",
        "GPU fps",
        "GPU ms",
        "host ms",
        "read MB",
        "atlas ms",
        "rays ms",
        "shade ms",
        "CPU ms",
        "CPU/GPU",
        "beams/level",
        "PSNR"
    );
    for name in scenes {
        let mut scene = scene::builtin(name).map_err(|e| e.to_string())?;
        scene.smesh.rest = smesh;
        let options = NonlinearOptions {
            degree,
            texels: 32,
            bounces: 2,
            // Area lights' caustics are left out (as in the runs before); point lights' are made
            // once for the frames: they depend on neither the camera nor the tree.
            caustic_strata: 0,
            shading: RenderOptions::exact(width, height),
        };
        let renderer = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let renderer = if rasterize { renderer.rasterized() } else { renderer };
        let renderer = if read_back { renderer.reading_levels_back() } else { renderer };
        let mut renderer = if read_image { renderer } else { renderer.displaying() };
        // The S mesh and the caustics depend on neither the camera nor the tree: made once, shared
        // by the frames.
        let (start, cpu_start) = (Instant::now(), our_threads_cpu_seconds());
        let mut shared = NonlinearPrecomputed::new(&scene, &options, &renderer).map_err(|e| e.to_string())?;
        let shared_cpu = cpu_since(cpu_start).map_or(0.0, |(main, workers)| main + workers);
        let shared_seconds = start.elapsed().as_secs_f64();
        let frame = |scene: &scene::Scene, renderer: &mut GpuBeams<'_>, shared: &mut NonlinearPrecomputed| {
            render_nonlinear_frame(scene, &options, renderer, &CpuBeams, Some(shared)).map_err(|e| e.to_string())
        };
        // The warm-up frame's image, for the PSNR: read back here where the renderer kept it.
        let (warm, _) = frame(&scene, &mut renderer, &mut shared)?;
        let cpu_start = our_threads_cpu_seconds();
        let warm = match warm {
            FrameImage::Read(image) => image,
            FrameImage::Kept(kept) => {
                let kept = GpuFrame::from_device(kept).map_err(|_| "the GPU kept no frame of its own")?;
                Image { width, height, pixels: kept.read_back(&gpu).map_err(|e| e.to_string())? }
            }
        };
        let read_image_cpu = cpu_since(cpu_start).map_or(0.0, |(main, workers)| main + workers);
        let (still, step) = (scene.camera, 1e-4 * scene.bounds().extent().length() * scene.camera.frame().right);
        let (before, traffic, reused) = (renderer.times(), gpu.traffic(), shared.beams_reused());
        let cpu_before = our_threads_cpu_seconds();
        let start = Instant::now();
        let mut stats = None;
        // Per timed frame, the CPU time of each of its stages.
        let mut frame_cpu: Vec<Vec<f64>> = Vec::new();
        for _ in 0..frames.max(1) {
            if moving {
                scene.camera.position += step;
                scene.camera.target += step;
            }
            let (image, made) = frame(&scene, &mut renderer, &mut shared)?;
            frame_cpu.push(made.stages.iter().map(|s| s.cpu_seconds).collect());
            stats = Some(made);
            // Where a display would show it.
            drop(image);
        }
        scene.camera = still;
        let per_frame = start.elapsed().as_secs_f64() / f64::from(frames.max(1));
        let cpu_time = cpu_since(cpu_before);
        let (after, traffic, reused) = (renderer.times(), gpu.traffic() - traffic, shared.beams_reused() - reused);
        let host = per_frame - traffic.waited_seconds / f64::from(frames.max(1));
        let read_mb = traffic.bytes_read_back as f64 / f64::from(frames.max(1)) / 1e6;
        let atlas = (after.atlas_seconds - before.atlas_seconds) / f64::from(frames.max(1));
        let rays = (after.ray_seconds - before.ray_seconds) / f64::from(frames.max(1));
        let shade = (after.shade_seconds - before.shade_seconds) / f64::from(frames.max(1));
        let start = Instant::now();
        let (cpu_image, _) =
            render_nonlinear_with(&scene, &options, &mut CpuBeams, &CpuBeams).map_err(|e| e.to_string())?;
        let cpu = start.elapsed().as_secs_f64();
        let psnr = difference(&warm, &cpu_image).map_err(|e| e.to_string())?.psnr;
        let stats = stats.unwrap_or_default();
        let levels: Vec<String> = stats.beams_per_level.iter().map(u64::to_string).collect();
        println!(
            "{name:<16} {:>9.2} {:>10.1} {:>9.1} {read_mb:>10.2} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>9.2} {:>13} {:>8}",
            1.0 / per_frame,
            1e3 * per_frame,
            1e3 * host,
            1e3 * atlas,
            1e3 * rays,
            1e3 * shade,
            1e3 * cpu,
            cpu / per_frame,
            levels.join("+"),
            if psnr.is_finite() { format!("{psnr:.1}") } else { "equal".into() },
        );
        let parts: Vec<String> =
            stats.stages.iter().map(|s| format!("{} {:.1}", s.name, 1e3 * s.host_seconds)).collect();
        println!("{:<16} host ms by stage: {}", "", parts.join(", "));
        if stats.stages.iter().any(|s| s.cpu_seconds > 0.0) {
            // Each stage's median over the timed frames (every frame has the same stages).
            let stage_median = |k: usize| median(frame_cpu.iter().filter_map(|f| f.get(k).copied()).collect());
            let parts: Vec<String> = (stats.stages.iter().enumerate())
                .map(|(k, s)| format!("{} {:.1}", s.name, 1e3 * stage_median(k)))
                .collect();
            let total: f64 = (0..stats.stages.len()).map(stage_median).sum();
            println!("{:<16} host CPU ms by stage ({:.1} in all): {}", "", 1e3 * total, parts.join(", "));
            let totals: Vec<f64> = frame_cpu.iter().map(|f| f.iter().sum()).collect();
            let each: Vec<String> = totals.iter().map(|s| format!("{:.1}", 1e3 * s)).collect();
            let median = median(totals);
            println!("{:<16} host CPU ms per timed frame: {} (median {:.1})", "", each.join(", "), 1e3 * median);
        }
        println!(
            "{:<16} mirror and glass pixels of the eye and tree texels kept on the GPU: {} (texels shaded: {}); \
             S mesh and caustics made once for the frames: {:.1} ms ({:.1} CPU ms, {} light beams)",
            "",
            stats.kept_on_backend,
            stats.texels_shaded,
            1e3 * shared_seconds,
            1e3 * shared_cpu,
            shared.stats().beams
        );
        let per = |seconds: f64| 1e3 * seconds / f64::from(frames.max(1));
        println!(
            "{:<16} host ms inside the GPU backend: uploads {:.1} ({:.1} MB), readbacks unpacked {:.1}, atlas \
             preparation {:.1}, Whitted rays past the tree {:.1}; points under coarse S-mesh faces composited on \
             the GPU: {:.0} (lookup jobs for the host: {:.0}); tree texels composited on the GPU: {:.0}",
            "",
            per(traffic.upload_seconds),
            traffic.bytes_uploaded as f64 / f64::from(frames.max(1)) / 1e6,
            per(traffic.unpack_seconds),
            per(after.prepare_seconds - before.prepare_seconds),
            per(after.whitted_host_seconds - before.whitted_host_seconds),
            (after.coarse_records - before.coarse_records) as f64 / f64::from(frames.max(1)),
            (after.lookups - before.lookups) as f64 / f64::from(frames.max(1)),
            (after.level_records - before.level_records) as f64 / f64::from(frames.max(1)),
        );
        let passes: Vec<f64> =
            after.atlas_pass_seconds.iter().zip(before.atlas_pass_seconds).map(|(a, b)| per(a - b)).collect();
        if passes.iter().any(|&ms| ms > 0.0) {
            let hits = if renderer.by_compute() {
                format!("nearest hits {:.1}", passes[1])
            } else {
                format!("draws {:.1}, gather {:.1}", passes[1], passes[2])
            };
            println!(
                "{:<16} GPU ms in atlas passes (timestamps): bounding triangles {:.1}, {hits}; {:.0} pages, {:.2} M \
                 (beam, triangle) pairs before the GPU's per-triangle culling",
                "",
                passes[0],
                (after.pages - before.pages) as f64 / f64::from(frames.max(1)),
                (after.triangles - before.triangles) as f64 / f64::from(frames.max(1)) / 1e6,
            );
        }
        println!(
            "{:<16} reused from the last frame's tree, per frame: {:.0} faces' beams, {:.0} beams' atlas preparations, \
             {:.0} beams' blocks",
            "",
            reused as f64 / f64::from(frames.max(1)),
            (after.beams_reused - before.beams_reused) as f64 / f64::from(frames.max(1)),
            (after.blocks_reused - before.blocks_reused) as f64 / f64::from(frames.max(1)),
        );
        if let Some((main, workers)) = cpu_time {
            println!(
                "{:<16} host CPU ms per frame: calling thread {:.1}, rayon workers {:.1}",
                "",
                per(main),
                per(workers),
            );
        }
        if !read_image {
            println!(
                "{:<16} the warm-up frame's image read back from the GPU (not in the timed frames): {:.1} host CPU ms",
                "",
                1e3 * read_image_cpu
            );
        }
    }
    println!(
        "GPU ms: whole frame; host ms: of it, time not blocked on the device (000 Table 2's CPU share: 1 to 25 ms \
         per frame at 1280×1024, with 52 to 3,400 beams per level; by stage: the last timed frame's (host CPU ms by \
         stage: the CPU time of our threads in each, which the software GPU's threads do not inflate, the median \
         of the timed frames', in all: the sum of those medians); inside the GPU backend: \
         per frame, overlapping the stages (atlas preparation: bounding-cone culling, packing, unpacking); host CPU ms: \
         CPU time of our threads, which a software GPU's own threads do not inflate as they do the wall-clock host \
         ms: the calling thread's is a lower bound of the host work, the workers' counts their spin-waits too); \
         read MB: bytes read back per frame; atlas ms: \
         beam visibility on the GPU (upload, bounding triangles, nearest hits, hit readback; GPU ms in atlas \
         passes: the device's own time in each, by timestamp queries where the adapter has them); rays ms: the \
         eye's rays; \
         shade ms: the GPU shading pass (area lights by 64 shadow rays), the Whitted rays past the last tree \
         level and the composite, radiance kept on the GPU; PSNR: GPU image vs the CPU's (exact soft \
         shadows)."
    );
    Ok(())
}

/// The CPU seconds of our threads since `start` (a reading of [`our_threads_cpu_seconds`]): the
/// calling thread's and the rayon workers'.
fn cpu_since(start: Option<(f64, f64)>) -> Option<(f64, f64)> {
    start.zip(our_threads_cpu_seconds()).map(|((m0, w0), (m1, w1))| (m1 - m0, w1 - w0))
}
