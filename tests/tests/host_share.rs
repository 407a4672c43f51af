//! A nonlinear frame's time split between host and device (000 Table 2's CPU / GPU column): the
//! frame's stages add up to its wall time, the GPU renderer's waits on the device are what its
//! stages' wall time exceeds their host time by, and its readbacks are counted. Skipped, saying
//! SKIPPED, without an adapter.

use beam_cpu::nonlinear::{CpuBeams, Degree, NonlinearOptions, render_nonlinear_with};
use beam_cpu::render::RenderOptions;
use beam_gpu::nonlinear::GpuBeams;
use beam_scene::scene;

fn options() -> NonlinearOptions {
    NonlinearOptions {
        degree: Degree::S3,
        texels: 8,
        bounces: 2,
        caustic_strata: 0,
        shading: RenderOptions { spp: 4, ..RenderOptions::exact(48, 32) },
    }
}

#[test]
fn cpu_frames_are_all_host_work() {
    let scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    let (_, stats) = render_nonlinear_with(&scene, &options(), &CpuBeams).expect("a render");
    let names: Vec<&str> = stats.stages.iter().map(|s| s.name).collect();
    for stage in ["eye view", "tree: rasterize beams", "radiance flow", "shading and composite"] {
        assert!(names.contains(&stage), "no stage {stage} in {names:?}");
    }
    let sum: f64 = stats.stages.iter().map(|s| s.seconds).sum();
    assert!((sum - stats.seconds).abs() <= 0.05 * stats.seconds + 2e-3, "stages {sum} s, frame {} s", stats.seconds);
    for s in &stats.stages {
        assert!((s.seconds - s.host_seconds).abs() < 1e-9, "{}: the CPU waited on no device", s.name);
    }
}

#[test]
fn gpu_frames_count_their_waits_and_readbacks() {
    let gpu = match beam_gpu::Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            assert!(!beam_conformance::gpu_required(), "BEAM_REQUIRE_GPU=1 but {e}");
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "SKIPPED: {e}");
            return;
        }
    };
    let scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    let renderer = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4);
    let before = gpu.traffic();
    let (_, stats) = render_nonlinear_with(&scene, &options(), &renderer).expect("a render");
    let traffic = gpu.traffic() - before;
    // At least the eye's hits (48 × 32 of them) and the final pixels came back.
    assert!(traffic.bytes_read_back >= 2 * 48 * 32 * 8, "{} bytes read back", traffic.bytes_read_back);
    assert!(traffic.waited_seconds > 0.0);
    // At least the eye's rays (32 bytes each) went up, and reading back took host time.
    assert!(traffic.bytes_uploaded >= 48 * 32 * 32, "{} bytes uploaded", traffic.bytes_uploaded);
    assert!(traffic.upload_seconds > 0.0 && traffic.unpack_seconds > 0.0, "{traffic:?}");
    assert!(traffic.upload_seconds + traffic.unpack_seconds < stats.seconds, "{traffic:?}");
    let waited_in_stages: f64 = stats.stages.iter().map(|s| s.seconds - s.host_seconds).sum();
    assert!(
        (waited_in_stages - traffic.waited_seconds).abs() < 1e-6 + 1e-3 * traffic.waited_seconds,
        "stages waited {waited_in_stages} s, the device counted {} s",
        traffic.waited_seconds
    );
    assert!(stats.stages.iter().all(|s| s.host_seconds <= s.seconds));
}
