//! The nonlinear renderer on a device whose storage bindings are narrower than a level of its beam
//! tree (000 §3, §7.3): every buffer that grows with S-mesh faces, beams or texels must be split or
//! compacted to fit one binding, and the image must still equal the CPU's.

use super::pixels::PixelDifference;
use super::twin::TwinShading;
use crate::property::{Config, Outcome};
use beam_cpu::nonlinear::CpuBeams;
use beam_gpu::nonlinear::{GpuBeams, GpuFace};
use beam_gpu::{Gpu, GpuError};
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_render::nonlinear::{CAUSTIC_STRATA, NonlinearOptions, render_nonlinear_with};
use beam_render::nonlinear::{Degree, SMesh};
use beam_render::options::RenderOptions;
use beam_scene::mesh;
use beam_scene::scene::{Bump, Camera, Light, Material, Scene};

/// Bytes of one storage binding on the narrowed device: the scene's triangles (48 bytes each), BVH
/// nodes and per-triangle shading (32 bytes each) fit, its S-mesh faces (128 bytes each), beams (576
/// bytes each) and deeper levels' texels do not.
pub(super) const NARROW_BINDING: u64 = 64 << 10;

/// A mirror ball and a glass ball (about 700 specular faces) on a checkered floor before a wall, a
/// red box, lit by a point light; the eye at `side`².
#[must_use]
pub(super) fn two_balls(side: u32) -> Scene {
    let mut tris: Vec<(Triangle, u32)> = Vec::new();
    let quad = |tris: &mut Vec<(Triangle, u32)>, o: Vec3, u: Vec3, v: Vec3, m: u32| {
        tris.push((Triangle::new(o, o + u, o + u + v), m));
        tris.push((Triangle::new(o, o + u + v, o + v), m));
    };
    for i in 0..6 {
        for j in 0..6 {
            let o = Vec3::new(-300.0 + 100.0 * i as f32, 0.0, -300.0 + 100.0 * j as f32);
            quad(&mut tris, o, Vec3::new(0.0, 0.0, 100.0), Vec3::new(100.0, 0.0, 0.0), (i + j) % 2);
        }
    }
    quad(&mut tris, Vec3::new(-300.0, 0.0, 300.0), Vec3::new(0.0, 400.0, 0.0), Vec3::new(600.0, 0.0, 0.0), 3);
    let add = |tris: &mut Vec<(Triangle, u32)>, m: &mesh::Mesh, material: u32| {
        tris.extend(m.triangles().into_iter().map(|t| (t, material)));
    };
    add(&mut tris, &mesh::cuboid(Vec3::new(150.0, 0.0, 100.0), Vec3::new(230.0, 90.0, 180.0)), 2);
    add(&mut tris, &mesh::sphere(Vec3::new(-90.0, 85.0, 20.0), 85.0, 14, 28), 4);
    add(&mut tris, &mesh::sphere(Vec3::new(80.0, 55.0, -90.0), 55.0, 8, 16), 5);
    let materials = vec![
        Material::Diffuse { albedo: Vec3::splat(0.75) },
        Material::Diffuse { albedo: Vec3::new(0.08, 0.1, 0.3) },
        Material::Diffuse { albedo: Vec3::new(0.7, 0.1, 0.08) },
        Material::Diffuse { albedo: Vec3::new(0.12, 0.5, 0.15) },
        Material::Mirror { tint: Vec3::splat(0.95), bump: Bump::NONE },
        Material::Glass { ior: 1.5 },
    ];
    let light = Light::Point { position: Vec3::new(60.0, 600.0, -250.0), intensity: Vec3::splat(1.0e6) };
    let camera = Camera {
        position: Vec3::new(40.0, 260.0, -480.0),
        target: Vec3::new(0.0, 60.0, 0.0),
        up: Vec3::Y,
        fov_y: 45.0,
        width: side,
        height: side,
    };
    Scene::new("two balls".into(), tris, materials, vec![light], camera)
}

/// wgpu's default adapter opened with storage bindings of at most `binding` bytes; without one,
/// `Ok(Err(outcome))` saying why the property is skipped, or the error itself when
/// `BEAM_REQUIRE_GPU=1`.
pub(super) fn narrow_adapter(binding: u64) -> Result<Result<Gpu, Outcome>, String> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
    let options = wgpu::RequestAdapterOptions { compatible_surface: None, ..Default::default() };
    let adapter = match pollster::block_on(instance.request_adapter(&options)) {
        Ok(a) => a,
        Err(e) if crate::property::gpu_required() => return Err(format!("BEAM_REQUIRE_GPU=1 but no GPU adapter: {e}")),
        Err(e) => return Ok(Err(Outcome::skipped(&format!("no GPU adapter: {e}")))),
    };
    let mut limits = adapter.limits();
    limits.max_storage_buffer_binding_size = limits.max_storage_buffer_binding_size.min(binding);
    let descriptor = wgpu::DeviceDescriptor { label: Some("narrow"), required_limits: limits, ..Default::default() };
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor)).map_err(|e| e.to_string())?;
    Ok(Ok(Gpu::from_device(device, queue, adapter.get_info())))
}

/// A nonlinear image (64², two levels, S1 and S3) of [`two_balls`] on a device whose storage bindings
/// hold [`NARROW_BINDING`] bytes — under its S-mesh faces' 128 bytes each, its beams' and its levels'
/// texels — rendered with the atlases, the ray tracer, the shading and the composite on the GPU
/// (no fallback to the CPU's composite), against the CPU renderer's with the same shading estimator:
/// at most 0.5% of the pixels differ by more than 4/255 in a channel (sRGB), as in
/// `gpu_images_equal_cpu`. A scene whose BVH does not fit a binding (`mirror-glass`) is refused
/// with [`GpuError::SceneTooLarge`].
pub(super) fn gpu_images_fit_narrow_bindings(_: crate::property::Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match narrow_adapter(NARROW_BINDING)? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let binding = beam_gpu::buffers::max_binding(&gpu);
    let scene = two_balls(64);
    let faces = SMesh::specular(&scene).faces.len() as u64;
    let face_bytes = faces * size_of::<GpuFace>() as u64;
    let triangle_bytes = scene.triangles.len() as u64 * 48;
    if face_bytes <= binding || triangle_bytes > binding {
        return Err(format!(
            "premise: {faces} faces ({face_bytes} B) must not fit a {binding} B binding, {} triangles \
             ({triangle_bytes} B) must",
            scene.triangles.len()
        ));
    }
    // What still must fit one binding, the scene's BVH, is refused with a typed error, not a wgpu
    // validation error.
    let big = beam_scene::scene::builtin("mirror-glass").map_err(|e| e.to_string())?;
    match GpuBeams::new(&gpu, &big) {
        Err(GpuError::SceneTooLarge { .. }) => {}
        Err(e) => return Err(format!("mirror-glass ({} triangles): {e}", big.triangles.len())),
        Ok(_) => return Err(format!("mirror-glass ({} triangles) fit {binding} B bindings", big.triangles.len())),
    }
    let (mut pixels, mut notes) = (0u64, Vec::new());
    for degree in [Degree::S1, Degree::S3] {
        let options = NonlinearOptions {
            degree,
            texels: 16,
            bounces: 2,
            caustic_strata: CAUSTIC_STRATA,
            shading: RenderOptions::exact(64, 64),
        };
        let mut renderer = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let (on_gpu, _) =
            render_nonlinear_with(&scene, &options, &mut renderer, &CpuBeams).map_err(|e| e.to_string())?;
        let times = renderer.times();
        if times.gpu_composites != 1 {
            return Err(format!("{degree:?}: the composite ran on the CPU ({} on the GPU)", times.gpu_composites));
        }
        let (on_cpu, _) = render_nonlinear_with(&scene, &options, &mut TwinShading::default(), &CpuBeams)
            .map_err(|e| e.to_string())?;
        let PixelDifference { differ, sum, n } = PixelDifference::of(&on_gpu, &on_cpu);
        if differ * 200 > n {
            return Err(format!("{degree:?}: {differ} of {n} pixels differ by more than 4/255"));
        }
        pixels += n;
        notes.push(format!(
            "{degree:?} {} pages, {} beams: {:.2}% (mean {:.2}/255)",
            times.pages,
            times.beams,
            100.0 * differ as f64 / n as f64,
            255.0 * sum / n as f64
        ));
    }
    Ok(Outcome {
        cases: pixels,
        note: format!(
            "{binding} B bindings, {faces} faces ({face_bytes} B), {} triangles; pixels differing by > 4/255: {}",
            scene.triangles.len(),
            notes.join(", ")
        ),
    })
}
