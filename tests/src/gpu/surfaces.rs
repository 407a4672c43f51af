//! Textured surfaces on the GPU: every method's GPU image of a scene with a base-colour texture, a
//! normal texture and a cut-out against the CPU's.

use super::device::adapter;
use crate::property::{Backend, Config, Outcome};
use beam_cpu::glossy::{gather_on_cpu, render_glossy_with};
use beam_cpu::nonlinear::CpuBeams;
use beam_cpu::render::{difference, render_queries};
use beam_gpu::glossy::GpuGather;
use beam_gpu::nonlinear::GpuBeams;
use beam_gpu::queries::GpuQueries;
use beam_math::Triangle;
use beam_math::glam::{Affine2, Vec2, Vec3};
use beam_render::glossy::{GlossyOptions, LightVolumes};
use beam_render::image::Image;
use beam_render::nonlinear::{Degree, NonlinearOptions, render_nonlinear_with};
use beam_render::options::{Method, RenderOptions};
use beam_scene::scene::surface::{AlphaCut, MaterialMaps, NormalMap, Surfaces, TextureRef};
use beam_scene::scene::texture::{Filter, Texture, Wrap};
use beam_scene::scene::{self, Environment, EnvironmentMap, Material, Scene};
use std::sync::Arc;

/// The image side.
const SIDE: u32 = 48;

/// Each GPU image (the host-driven beam and ray frames, the nonlinear beams, the glossy light
/// volumes) of `mirror-glass-coarse` dressed in textures — its white walls checkered by a
/// base-colour texture, its green wall bent by a normal texture, and a lattice (`alphaMode`
/// `MASK`) standing before the mirror sphere, seen directly and in the mirror and casting its
/// shadow — and the nonlinear image of the plain scene under a sky map (seen through the open
/// front, in the mirror and through the glass), against the CPU's image of the same frame: PSNR
/// ≥ 45 dB each (a beam the GPU drew through the lattice as opaque, a textured point it shaded as
/// its material's constant, or a texel that left the scene drawn black costs far more). Each
/// PSNR is stated.
pub(super) fn gpu_textured_surfaces_equal_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let scene = dressed()?;
    let mut images: Vec<(&str, Image, Image)> = Vec::new();
    let queries = GpuQueries::new(&gpu, &scene).map_err(text)?;
    for (name, method) in [("beam", Method::Beam), ("ray", Method::Ray)] {
        let options = RenderOptions { method, spp: 16, ..RenderOptions::exact(SIDE, SIDE) };
        let cpu = render_queries(&scene, &options, &CpuBeams, || {}).map_err(text)?.0;
        let on_gpu = render_queries(&scene, &options, &queries, || {}).map_err(text)?.0;
        images.push((name, cpu, on_gpu));
    }
    let options = NonlinearOptions {
        degree: Degree::S3,
        texels: 32,
        bounces: 2,
        // No caustics: `gpu_images_equal_cpu` checks those; here they would only cost time.
        caustic_strata: 0,
        shading: RenderOptions::exact(SIDE, SIDE),
    };
    let mut sky = scene::builtin("mirror-glass-coarse").map_err(text)?;
    sky.environment = Environment::Map(Arc::new(sky_map()));
    for (name, scene) in [("nonlinear", &scene), ("nonlinear under a sky", &sky)] {
        let mut beams = GpuBeams::new(&gpu, scene).map_err(text)?;
        let on_gpu = render_nonlinear_with(scene, &options, &mut beams, &CpuBeams).map_err(text)?.0;
        let cpu = render_nonlinear_with(scene, &options, &mut CpuBeams, &CpuBeams).map_err(text)?.0;
        images.push((name, cpu, on_gpu));
    }
    let options = GlossyOptions::new(SIDE, SIDE);
    let gather = GpuGather::new(&gpu, &scene).map_err(text)?;
    let run = |v: &LightVolumes, points: &[(Vec3, Vec3)]| gather.gather(&gpu, v, points, &options).map_err(Into::into);
    let on_gpu = render_glossy_with(&scene, &options, &CpuBeams, &run).map_err(text)?.0;
    let run = |v: &LightVolumes, points: &[(Vec3, Vec3)]| Ok(gather_on_cpu(&scene, v, points, &options));
    let cpu = render_glossy_with(&scene, &options, &CpuBeams, &run).map_err(text)?.0;
    images.push(("glossy", cpu, on_gpu));
    let mut notes = Vec::new();
    for (name, cpu, on_gpu) in &images {
        let d = difference(cpu, on_gpu).map_err(text)?;
        if d.psnr < 45.0 {
            return Err(format!("{name}: PSNR {:.1} dB (max {:.3})", d.psnr, d.max));
        }
        notes.push(format!("{name} {:.1} dB", d.psnr));
    }
    Ok(Outcome { cases: images.len() as u64 * u64::from(SIDE * SIDE), note: format!("PSNR {}", notes.join(", ")) })
}

/// An error's message.
fn text(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// `mirror-glass-coarse` with textured walls and a lattice cut out of a quad before its mirror
/// sphere (texture coordinates `(x + z, y + z) / 185` on every triangle).
fn dressed() -> Result<Scene, String> {
    let base = scene::builtin("mirror-glass-coarse").map_err(text)?;
    let mut materials = base.materials.clone();
    let lattice = materials.len() as u32;
    materials.push(Material::Diffuse { albedo: Vec3::new(0.8, 0.6, 0.3) });
    let mut triangles: Vec<(Triangle, u32)> =
        base.triangles.iter().copied().zip(base.material_of.iter().copied()).collect();
    let p = |x: f32, y: f32| Vec3::new(x, y, 40.0);
    let (a, b, c, d) = (p(40.0, 0.0), p(330.0, 0.0), p(330.0, 240.0), p(40.0, 240.0));
    triangles.extend([(Triangle::new(a, b, c), lattice), (Triangle::new(a, c, d), lattice)]);
    let mut surfaces = Surfaces::default();
    surfaces.uv[0] = triangles.iter().map(|(t, _)| t.v.map(|v| Vec2::new(v.x + v.z, v.y + v.z) / 185.0)).collect();
    // 0: a checker; 1: a normal texture tilting alternate texels ±30° along u; 2: a lattice whose
    // bars (alpha 1) are a quarter of each cell.
    let checker = |x: u32, y: u32| if (x + y) % 2 == 0 { [230, 230, 230, 255] } else { [60, 90, 160, 255] };
    let bent = |x: u32, _: u32| if x % 2 == 0 { [64, 128, 222, 255] } else { [192, 128, 222, 255] };
    let bars = |x: u32, y: u32| [255, 255, 255, if x % 4 == 0 || y % 4 == 0 { 255 } else { 0 }];
    surfaces.textures = vec![texture(4, &checker), texture(4, &bent), texture(16, &bars)];
    let at = |texture| TextureRef { texture, tex_coord: 0, transform: Affine2::IDENTITY };
    surfaces.maps = vec![MaterialMaps::default(); materials.len()];
    surfaces.maps[0].base_color = Some(at(0));
    surfaces.maps[2].normal = Some(NormalMap { texture: at(1), scale: 1.0 });
    surfaces.maps[lattice as usize].alpha = Some(AlphaCut { factor: 1.0, texture: Some(at(2)), cutoff: Some(0.5) });
    let mut scene =
        Scene::with_surfaces("dressed".into(), triangles, materials, base.lights.clone(), base.camera, surfaces);
    scene.smesh = base.smesh.clone();
    Ok(scene)
}

/// A sky brighter and bluer upwards, banded by azimuth, so that every reflected direction shows.
fn sky_map() -> EnvironmentMap {
    let (w, h) = (64, 32);
    let texels = (0..w * h)
        .map(|i| {
            let d = EnvironmentMap::direction(((i % w) as f32 + 0.5) / w as f32, ((i / w) as f32 + 0.5) / h as f32);
            let band = if (i % w) / 8 % 2 == 0 { 1.0 } else { 0.6 };
            band * Vec3::new(0.4 + 0.2 * d.x, 0.5 + 0.3 * d.y, 0.6 + 0.4 * d.y)
        })
        .collect();
    EnvironmentMap::new(w, h, texels).expect("a valid map")
}

/// A `side`² texture of texels `rgba(x, y)`, repeated, read at the nearest texel.
fn texture(side: u32, rgba: &dyn Fn(u32, u32) -> [u8; 4]) -> Texture {
    Texture {
        width: side,
        height: side,
        texels: (0..side * side).map(|i| rgba(i % side, i / side)).collect::<Vec<_>>().into(),
        wrap: [Wrap::Repeat; 2],
        filter: Filter::Nearest,
    }
}
