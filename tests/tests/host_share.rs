//! A nonlinear frame's time split between host and device (000 Table 2's CPU / GPU column): the
//! frame's stages add up to its wall time, the GPU renderer's waits on the device are what its
//! stages' wall time exceeds their host time by, and its readbacks are counted; a frame that takes
//! its beams from the frame before is the frame that makes them. The GPU's skipped, saying SKIPPED,
//! without an adapter.

use beam_cpu::nonlinear::CpuBeams;
use beam_gpu::nonlinear::{GpuBeams, GpuFrame};
use beam_render::nonlinear::BeamRenderer;
use beam_render::nonlinear::Degree;
use beam_render::nonlinear::{
    FrameImage, NonlinearOptions, NonlinearPrecomputed, render_nonlinear_frame, render_nonlinear_with,
};
use beam_render::options::RenderOptions;
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
    let (_, stats) = render_nonlinear_with(&scene, &options(), &mut CpuBeams, &CpuBeams).expect("a render");
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

/// The adapter, or `None` after saying SKIPPED (a failure where `BEAM_REQUIRE_GPU=1`).
fn gpu() -> Option<beam_gpu::Gpu> {
    match beam_gpu::Gpu::new() {
        Ok(gpu) => Some(gpu),
        Err(e) => {
            assert!(!beam_conformance::gpu_required(), "BEAM_REQUIRE_GPU=1 but {e}");
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "SKIPPED: {e}");
            None
        }
    }
}

/// Frames sharing what they precompute keep their trees' beams for the next frame: a second frame
/// from the same eye at another size (other regions; the eye's beams the same, deeper ones fitted
/// to other texels) takes the eye's beams from the first, and its pixels are, bit for bit, those of
/// a frame that makes them all afresh (`fresh`: a renderer that has rendered nothing). Returns how
/// many faces' beams the second frame found.
fn frames_reusing_beams_equal_fresh(renderer: &mut dyn BeamRenderer, fresh: &mut dyn BeamRenderer) -> u64 {
    let scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    let first = options();
    let second = NonlinearOptions { shading: RenderOptions { spp: 4, ..RenderOptions::exact(40, 28) }, ..first };
    let mut shared = NonlinearPrecomputed::new(&scene, &first, renderer).expect("the precomputed");
    render_nonlinear_frame(&scene, &first, renderer, &CpuBeams, Some(&mut shared)).expect("a first frame");
    let found = shared.beams_reused();
    let (reused, stats) =
        render_nonlinear_frame(&scene, &second, renderer, &CpuBeams, Some(&mut shared)).expect("a second frame");
    let (made, _) = render_nonlinear_with(&scene, &second, fresh, &CpuBeams).expect("a fresh frame");
    assert_eq!(
        reused.read().map(|r| r.pixels),
        Some(made.pixels),
        "a frame reusing its beams differs from one making them"
    );
    let beams = stats.beams_per_level.iter().sum::<u64>();
    assert!(beams > 0);
    shared.beams_reused() - found
}

#[test]
fn cpu_frames_reusing_beams_equal_fresh_ones() {
    assert!(frames_reusing_beams_equal_fresh(&mut CpuBeams, &mut CpuBeams) > 0, "the second frame found no beam");
}

#[test]
fn gpu_frames_reusing_beams_equal_fresh_ones() {
    let Some(gpu) = gpu() else { return };
    let scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    let mut renderer = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4);
    let mut fresh = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4);
    let before = renderer.times().beams_reused;
    assert!(frames_reusing_beams_equal_fresh(&mut renderer, &mut fresh) > 0, "the second frame found no beam");
    let prepared = renderer.times().beams_reused - before;
    assert!(prepared > 0, "the second frame's atlas prepared every beam again");
}

/// A frame after the eye moved a little prepares its beams afresh but takes the BVH blocks the
/// last frame gathered with wider cones, and equals, bit for bit, the frame a fresh renderer makes;
/// so does one after a larger move, where fewer beams (or none) take them.
#[test]
fn gpu_frames_of_a_moved_eye_equal_fresh_ones() {
    let Some(gpu) = gpu() else { return };
    let mut scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    let mut renderer = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4);
    let options = NonlinearOptions { shading: RenderOptions { spp: 4, ..RenderOptions::exact(40, 28) }, ..options() };
    let mut shared = NonlinearPrecomputed::new(&scene, &options, &renderer).expect("the precomputed");
    render_nonlinear_frame(&scene, &options, &mut renderer, &CpuBeams, Some(&mut shared)).expect("a first frame");
    let mut took = Vec::new();
    for step in [1e-4, 0.25] {
        let step = step * scene.bounds().extent().length() * scene.camera.frame().right;
        scene.camera.position += step;
        scene.camera.target += step;
        let before = renderer.times().blocks_reused;
        let (moved, _) = render_nonlinear_frame(&scene, &options, &mut renderer, &CpuBeams, Some(&mut shared))
            .expect("a moved frame");
        took.push(renderer.times().blocks_reused - before);
        let mut fresh = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4);
        let (made, _) = render_nonlinear_with(&scene, &options, &mut fresh, &CpuBeams).expect("a fresh frame");
        let moved = moved.read().expect("a frame read back").pixels;
        let differ = moved.iter().zip(&made.pixels).filter(|(a, b)| a != b).count();
        assert!(
            moved.len() == made.pixels.len() && differ == 0,
            "a moved frame differs from a fresh one in {differ} pixels"
        );
    }
    assert!(took[0] > 0 && took[1] < took[0], "beams that took an earlier frame's blocks: {took:?}");
}

#[test]
fn gpu_frames_count_their_waits_and_readbacks() {
    let Some(gpu) = gpu() else { return };
    let scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    let mut renderer = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4);
    let before = gpu.traffic();
    let (_, stats) = render_nonlinear_with(&scene, &options(), &mut renderer, &CpuBeams).expect("a render");
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

/// A renderer that keeps its frames on the GPU for display reads none back: the frame returns no
/// image and reads back at least the image's bytes less than the same frame read back, and its texture, of the image's shape (40 pixels, a row of 320 bytes: not a whole copy
/// alignment), holds the pixels a renderer that reads them back returns, bit for bit; it is
/// handed over once.
#[test]
fn gpu_frames_kept_for_display_equal_frames_read_back() {
    let Some(gpu) = gpu() else { return };
    let scene = scene::builtin("facing-mirrors-coarse").expect("a built-in");
    let options = NonlinearOptions { shading: RenderOptions { spp: 4, ..RenderOptions::exact(40, 28) }, ..options() };
    let mut reading = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4);
    let before = gpu.traffic();
    let (read, _) = render_nonlinear_with(&scene, &options, &mut reading, &CpuBeams).expect("a frame read back");
    let read_frame = (gpu.traffic() - before).bytes_read_back;
    let mut displaying = GpuBeams::new(&gpu, &scene).expect("the GPU renderer").with_light_samples(4).displaying();
    let before = gpu.traffic();
    let (image, _) = render_nonlinear_frame(&scene, &options, &mut displaying, &CpuBeams, None).expect("a frame kept");
    let read_back = (gpu.traffic() - before).bytes_read_back;
    let FrameImage::Kept(image) = image else { panic!("a frame kept for display came back as an image") };
    // The same frame, less its pixels (four half floats each).
    assert!(read_back + 40 * 28 * 8 <= read_frame, "{read_back} bytes read back for a frame kept, {read_frame} read");
    let frame = GpuFrame::from_device(image).expect("the GPU's frame");
    let size = frame.texture().size();
    assert_eq!((size.width, size.height), (40, 28));
    assert_eq!(frame.read_back(&gpu).expect("the frame's pixels"), read.pixels);
    let one_shot = render_nonlinear_with(&scene, &options, &mut displaying, &CpuBeams);
    assert!(matches!(one_shot, Err(beam_render::nonlinear::NonlinearError::FrameKept)), "{:?}", one_shot.map(|_| ()));
}
