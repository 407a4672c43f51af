//! The G-buffer pass engines run on their own device (`beam_gpu::gbuffer`) against its CPU twin.

use super::device::adapter;
use crate::property::{Backend, Config, Outcome};
use beam_cpu::render::light_seen;
use beam_gpu::Gpu;
use beam_gpu::buffers::{read_back, storage};
use beam_gpu::gbuffer::{GBuffer, GBufferShadows, area_lights};
use beam_math::glam::Vec3;
use beam_render::queries::LightQuery;
use beam_render::tolerance::shading_eps;
use beam_scene::scene::{self, Scene};
use rayon::prelude::*;

/// A camera's G-buffer of `scene` at `size`², as an engine would rasterize it: positions (`w` 1 on
/// a surface) and normals facing the camera.
fn gbuffer_of(scene: &Scene, size: u32) -> (Vec<[f32; 4]>, Vec<[f32; 4]>) {
    let camera = scene.camera.with_size(size, size);
    let frame = camera.frame();
    (0..(size * size) as usize)
        .into_par_iter()
        .map(|i| {
            let ray = camera.pixel_ray(&frame, i);
            match scene.wide.closest_hit(ray, f32::INFINITY) {
                Some(hit) => {
                    let n = scene.normal(hit.prim);
                    let n = if n.dot(ray.direction) > 0.0 { -n } else { n };
                    (ray.at(hit.t).extend(1.0).to_array(), n.extend(0.0).to_array())
                }
                None => ([0.0; 4], [0.0; 4]),
            }
        })
        .unzip()
}

/// The pass's texture for `scene`'s G-buffer at `size`² with `shadows`, read back, and the beams
/// it says stopped short.
fn irradiance_on(
    gpu: &Gpu,
    shadows: &GBufferShadows,
    positions: &[[f32; 4]],
    normals: &[[f32; 4]],
    size: u32,
) -> Result<(Vec<[f32; 4]>, u32), String> {
    let (p, n) = (
        storage(gpu, "positions", positions, wgpu::BufferUsages::empty()),
        storage(gpu, "normals", normals, wgpu::BufferUsages::empty()),
    );
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Float,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    let gbuffer = GBuffer { positions: &p, normals: &n, width: size, height: size };
    shadows.encode(gpu, &mut encoder, &gbuffer, &texture.create_view(&Default::default()));
    // Rows of a texture copy are 256-byte aligned: sizes here are multiples of 16 pixels.
    let bytes = u64::from(size * size * 16);
    let copy = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: bytes,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &copy,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size * 16), rows_per_image: None },
        },
        texture.size(),
    );
    let texels = read_back::<[f32; 4]>(gpu, encoder, &copy, bytes).map_err(|e| e.to_string())?;
    Ok((texels, shadows.stopped_short(gpu).map_err(|e| e.to_string())?))
}

/// The G-buffer pass on the Cornell box (64²) and `mirror-glass` (48²; its lights' beams pass its
/// glass and mirror triangles as occluders) against `Σ radiance × light_seen(…).irradiance` per
/// pixel (exact shading, the point lifted by the scene's shading tolerance): within 1e-4 of the
/// brightest pixel's value at 99% of the pixels and 1e-3 at all, none stopped short; then with a
/// work budget of 40 loop iterations a pixel, every pixel with a light in front of it stops
/// short, says so in its alpha, and the count adds up.
pub(super) fn gpu_gbuffer_irradiance_equals_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let mut notes = Vec::new();
    let mut cases = 0u64;
    for (name, size) in [("cornell", 64), ("mirror-glass", 48)] {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let (positions, normals) = gbuffer_of(&scene, size);
        let shadows = GBufferShadows::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let (texels, short) = irradiance_on(&gpu, &shadows, &positions, &normals, size)?;
        let lights = area_lights(&scene);
        let eps = shading_eps(&scene);
        let expected: Vec<Vec3> = positions
            .par_iter()
            .zip(&normals)
            .map(|(p, n)| {
                if p[3] == 0.0 {
                    return Vec3::ZERO;
                }
                let n = Vec3::from_slice(&n[..3]);
                let p = Vec3::from_slice(&p[..3]) + eps * n;
                lights
                    .iter()
                    .map(|(l, radiance)| {
                        *radiance
                            * light_seen(
                                &scene.bvh,
                                &scene.triangles,
                                l,
                                &LightQuery { p, n, light: 0, clip_above: true },
                            )
                            .irradiance
                    })
                    .sum()
            })
            .collect();
        let scale = expected.iter().map(|e| e.max_element()).fold(0.0f32, f32::max).max(1e-30);
        let (mut beyond, mut worst) = (0usize, 0.0f32);
        for (i, (t, e)) in texels.iter().zip(&expected).enumerate() {
            let d = (Vec3::from_slice(&t[..3]) - *e).abs().max_element() / scale;
            worst = worst.max(d);
            beyond += usize::from(d > 1e-4);
            if d > 1e-3 || t[3] != 0.0 {
                return Err(format!("{name} pixel {i}: GPU {t:?}, CPU {e} (alpha = beams stopped short)"));
            }
        }
        if short != 0 || beyond * 100 > texels.len() {
            return Err(format!("{name}: {short} beams stopped short, {beyond} pixels beyond 1e-4"));
        }
        // A budget too small for any beam: every lit-side pixel says so.
        let tight = GBufferShadows::new(&gpu, &scene).map_err(|e| e.to_string())?.with_budget(40);
        let (texels, short) = irradiance_on(&gpu, &tight, &positions, &normals, size)?;
        let marked: u32 = texels.iter().map(|t| t[3] as u32).sum();
        if short == 0 || marked != short {
            return Err(format!("{name} with a budget of 40: {short} beams stopped short, pixels mark {marked}"));
        }
        notes.push(format!(
            "{name}: max |Δ| {worst:.1e} of the brightest, {beyond} beyond 1e-4; budget 40: {short} beams marked"
        ));
        cases += texels.len() as u64;
    }
    Ok(Outcome { cases, note: notes.join("; ") })
}
