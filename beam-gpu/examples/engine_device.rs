//! Use beam's GPU ray tracer on a wgpu device your engine already owns, and take beam's WGSL for
//! your own pipelines, as source text or as a naga module.
//!
//! `cargo run --release -p beam-gpu --example engine_device` (any adapter: Mesa's lavapipe where
//! there is no GPU; without one it says so and stops, or fails under `BEAM_REQUIRE_GPU=1`)

use beam_bvh::gpu::GpuBvh;
use beam_gpu::Gpu;
use beam_gpu::interface::MISS;
use beam_gpu::raytrace::{GpuRay, RayTracer};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The engine's device and queue, made the engine's way (here: headless, the adapter's limits).
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
    let options = wgpu::RequestAdapterOptions { compatible_surface: None, ..Default::default() };
    let adapter = match pollster::block_on(instance.request_adapter(&options)) {
        Ok(adapter) => adapter,
        Err(e) if std::env::var("BEAM_REQUIRE_GPU").as_deref() == Ok("1") => {
            return Err(format!("no adapter: {e}").into());
        }
        Err(e) => {
            println!("SKIPPED: no GPU adapter ({e})");
            return Ok(());
        }
    };
    let descriptor = wgpu::DeviceDescriptor { required_limits: adapter.limits(), ..Default::default() };
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))?;
    // Lend them to beam: it records its own passes on them and waits for its own work only.
    let gpu = Gpu::from_device(device, queue, adapter.get_info());

    // A scene's BVH in the GPU layout (a built-in here; yours through beam_scene or your own
    // triangles), and the nearest hits of a 64 × 64 camera's rays.
    let scene = beam_scene::scene::builtin("cornell")?;
    let tracer = RayTracer::new(&gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)?)?;
    let camera = scene.camera.with_size(64, 64);
    let frame = camera.frame();
    let rays: Vec<GpuRay> = (0..64 * 64).map(|i| GpuRay::closest(&camera.pixel_ray(&frame, i))).collect();
    let hits = tracer.trace(&gpu, &rays)?;
    let hit = hits.iter().filter(|h| h.prim != MISS).count();
    println!("{}: {hit} of {} camera rays hit the Cornell box", gpu.describe(), rays.len());

    // The WGSL, for pipelines of your own: the full source (shared code and generated constants
    // included) and the naga module it parses to.
    let source = beam_gpu::shaders::source("raytrace").ok_or("no shader named raytrace")?;
    let (module, _) = beam_gpu::shaders::validate("raytrace")?;
    let entries: Vec<&str> = module.entry_points.iter().map(|e| e.name.as_str()).collect();
    println!("raytrace.wgsl: {} bytes, entry points {entries:?}", source.len());
    Ok(())
}
