//! Exact soft shadows into an engine's own texture: the engine owns the wgpu device, has a
//! G-buffer (positions and normals) on it, and asks beam for the irradiance of every pixel from
//! the scene's area lights; beam records one compute pass into the engine's encoder and reads
//! nothing back.
//!
//! `cargo run --release -p beam-gpu --example engine_shadows` (any adapter: Mesa's lavapipe where
//! there is no GPU; without one it says so and stops, or fails under `BEAM_REQUIRE_GPU=1`)

use beam_bvh::gpu::GpuBvh;
use beam_gpu::Gpu;
use beam_gpu::buffers::{read_back, storage};
use beam_gpu::gbuffer::{GBuffer, GBufferShadows};
use beam_gpu::interface::MISS;
use beam_gpu::raytrace::{GpuRay, RayTracer};

const SIZE: u32 = 64;

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
    let gpu = Gpu::from_device(device, queue, adapter.get_info());

    // The engine's G-buffer. An engine rasterizes it; here the Cornell box's camera rays stand in
    // (beam's ray tracer, positions and normals made on the host and uploaded once).
    let scene = beam_scene::scene::builtin("cornell")?;
    let tracer = RayTracer::new(&gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)?)?;
    let camera = scene.camera.with_size(SIZE, SIZE);
    let frame = camera.frame();
    let rays: Vec<_> = (0..(SIZE * SIZE) as usize).map(|i| camera.pixel_ray(&frame, i)).collect();
    let hits = tracer.trace(&gpu, &rays.iter().map(GpuRay::closest).collect::<Vec<_>>())?;
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    for (ray, hit) in rays.iter().zip(&hits) {
        if hit.prim == MISS {
            positions.push([0.0f32; 4]);
            normals.push([0.0f32; 4]);
            continue;
        }
        let n = scene.normal(hit.prim);
        let n = if n.dot(ray.direction) > 0.0 { -n } else { n };
        positions.push(ray.at(hit.t).extend(1.0).to_array());
        normals.push(n.extend(0.0).to_array());
    }
    let positions = storage(&gpu, "positions", &positions, wgpu::BufferUsages::empty());
    let normals = storage(&gpu, "normals", &normals, wgpu::BufferUsages::empty());
    let gbuffer = GBuffer { positions: &positions, normals: &normals, width: SIZE, height: SIZE };

    // The engine's irradiance texture, written by beam's pass in the engine's encoder.
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("irradiance"),
        size: wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Float,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    let shadows = GBufferShadows::new(&gpu, &scene)?;
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    shadows.encode(&gpu, &mut encoder, &gbuffer, &view);
    // (The engine would go on to its lighting pass, sampling `texture`.)
    gpu.submit([encoder.finish()]);

    // Only to print something: the texture's mean irradiance and the beams that stopped short.
    let copy = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("irradiance copy"),
        size: u64::from(SIZE * SIZE * 16),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &copy,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(SIZE * 16), rows_per_image: None },
        },
        texture.size(),
    );
    let texels: Vec<[f32; 4]> = read_back(&gpu, encoder, &copy, u64::from(SIZE * SIZE * 16))?;
    let lit = texels.iter().filter(|t| t[0] + t[1] + t[2] > 0.0).count();
    let mean = texels.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0).sum::<f32>() / texels.len() as f32;
    println!(
        "{}: {SIZE}×{SIZE} G-buffer, {lit} pixels lit, mean irradiance {mean:.3}, {} beams stopped short",
        gpu.describe(),
        shadows.stopped_short(&gpu)?
    );
    Ok(())
}
