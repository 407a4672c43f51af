//! A normal texture bends the shading normal: a floor whose texture tilts every normal by 30°
//! towards +u (or towards decreasing v, up in the image: glTF's green channel) is lit by a point
//! light as a floor of that normal is, exactly, by beams and by rays, and by the glossy light
//! volumes' direct light and its reference's; and the host-driven wavefront frame (what the GPU's
//! `beam` and `ray` frames run) lights it as the CPU renderer does.

use beam_cpu::glossy::{render_glossy, render_glossy_reference};
use beam_cpu::nonlinear::CpuBeams;
use beam_cpu::render::{difference, render, render_queries};
use beam_math::Triangle;
use beam_math::glam::{Affine2, Vec2, Vec3};
use beam_render::glossy::GlossyOptions;
use beam_render::options::{Method, RenderOptions};
use beam_scene::scene::surface::{MaterialMaps, NormalMap, Surfaces, TextureRef};
use beam_scene::scene::texture::{Filter, Texture, Wrap};
use beam_scene::scene::{Camera, Environment, Light, Material, Scene};
use std::sync::Arc;

const SIDE: u32 = 33;

/// The floor `x, z ∈ [−1, 1]` facing up, `u = (x + 1) / 2`, `v = (z + 1) / 2`, of one material
/// whose normal texture is the single texel `rgb`; a point light at `light`; a camera looking
/// straight down at the origin (the centre pixel's ray meets the floor there).
fn floor(rgb: [u8; 3], light: Vec3) -> Scene {
    let p = |x: f32, z: f32| Vec3::new(x, 0.0, z);
    let (a, b, c, d) = (p(-1.0, -1.0), p(-1.0, 1.0), p(1.0, 1.0), p(1.0, -1.0));
    let triangles = vec![(Triangle::new(a, b, c), 0), (Triangle::new(a, c, d), 0)];
    let uv = |t: &Triangle| t.v.map(|v| Vec2::new((v.x + 1.0) / 2.0, (v.z + 1.0) / 2.0));
    let mut surfaces = Surfaces::default();
    surfaces.uv[0] = triangles.iter().map(|(t, _)| uv(t)).collect();
    surfaces.textures.push(Texture {
        width: 1,
        height: 1,
        texels: Arc::new([[rgb[0], rgb[1], rgb[2], 255]]),
        wrap: [Wrap::Repeat; 2],
        filter: Filter::Nearest,
    });
    let texture = TextureRef { texture: 0, tex_coord: 0, transform: Affine2::IDENTITY };
    surfaces.maps = vec![MaterialMaps { normal: Some(NormalMap { texture, scale: 1.0 }), ..MaterialMaps::default() }];
    let camera = Camera {
        position: Vec3::new(0.0, 3.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::Z,
        fov_y: 40.0,
        width: SIDE,
        height: SIDE,
    };
    let lights = vec![Light::Point { position: light, intensity: Vec3::splat(10.0) }];
    let materials = vec![Material::Diffuse { albedo: Vec3::splat(0.5) }];
    Scene::with_surfaces("normal-mapped floor".into(), triangles, materials, lights, camera, surfaces)
}

/// The radiance of the centre pixel under `options` (`wavefront`: by the host-driven frame, its
/// queries answered by the CPU).
fn centre(scene: &Scene, options: &RenderOptions, wavefront: bool) -> f32 {
    let image = if wavefront {
        render_queries(scene, options, &CpuBeams, || {}).expect("the CPU answers every query").0
    } else {
        render(scene, options, || {}).0
    };
    image.pixels[(SIDE * SIDE / 2) as usize].x
}

/// The radiance of the centre pixel by the glossy light volumes (`reference`: by their photon
/// reference).
fn glossy_centre(scene: &Scene, reference: bool) -> f32 {
    let image = if reference {
        render_glossy_reference(scene, SIDE, SIDE, 1_000, 1).expect("a reference")
    } else {
        render_glossy(scene, &GlossyOptions::new(SIDE, SIDE)).expect("a render").0
    };
    image.pixels[(SIDE * SIDE / 2) as usize].x
}

/// What a diffuse point at the origin of albedo ½ and unit normal `n` sends up from the light.
fn expected(n: Vec3, light: Vec3) -> f32 {
    0.5 / std::f32::consts::PI * 10.0 * n.dot(light.normalize()).max(0.0) / light.length_squared()
}

#[test]
fn a_normal_texture_bends_the_light_a_point_receives() {
    let (s, c) = (0.5f32, 3f32.sqrt() / 2.0);
    // The texel of tangent-space normal (x, y, z): (x + 1) / 2 in 8 bits.
    let texel = |n: Vec3| ((n + Vec3::ONE) / 2.0 * 255.0).round().to_array().map(|v| v as u8);
    let decoded = |t: [u8; 3]| (Vec3::from(t.map(f32::from)) / 255.0 * 2.0 - Vec3::ONE).normalize();
    let exact = RenderOptions::exact(SIDE, SIDE);
    let rays = RenderOptions { method: Method::Ray, ..exact };
    let eye_beams = RenderOptions { primary_beams: true, ..exact };
    // The floor's frame: tangent +x (along u), up the image −z (v grows with z), normal +y.
    let world = |t: Vec3| Vec3::new(t.x, t.z, -t.y);
    // Towards +u, and towards +y in the texture (glTF's green channel).
    for tangent in [Vec3::new(s, 0.0, c), Vec3::new(0.0, s, c)] {
        let rgb = texel(tangent);
        let n = world(decoded(rgb));
        for light in
            [Vec3::new(2.0, 2.0, 0.0), Vec3::new(-2.0, 2.0, 0.0), Vec3::new(0.0, 2.0, 2.0), Vec3::new(0.0, 2.0, -2.0)]
        {
            let scene = floor(rgb, light);
            let want = expected(n, light);
            for (name, options) in [("beams", &exact), ("rays", &rays), ("eye beams", &eye_beams)] {
                for wavefront in [false, true] {
                    let got = centre(&scene, options, wavefront);
                    assert!(
                        (got - want).abs() <= 0.02 * want + 1e-6,
                        "{name} (wavefront {wavefront}), light at {light}: {got} against {want}"
                    );
                }
            }
            for reference in [false, true] {
                let got = glossy_centre(&scene, reference);
                let name = if reference { "glossy reference" } else { "glossy" };
                assert!((got - want).abs() <= 0.02 * want + 1e-6, "{name}, light at {light}: {got} against {want}");
            }
            // Unbent, the floor would get a visibly different amount wherever the light is not
            // across the tilt's axis.
            let flat = expected(Vec3::Y, light);
            if n.dot(light.normalize()) != Vec3::new(0.0, n.y, 0.0).dot(light.normalize()) {
                assert!((flat - want).abs() > 0.1 * want, "the tilt changes the light: {flat} against {want}");
            }
        }
    }
}

#[test]
fn beams_and_rays_agree_under_a_light_that_crosses_the_surface() {
    // Tilted 60° towards +x, facing a wall light at x = 2 that reaches below the floor's plane: the
    // part below is above the bent normal's horizon but hidden by the floor itself.
    let bent = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
    let rgb = ((bent + Vec3::ONE) / 2.0 * 255.0).round().to_array().map(|v| v as u8);
    let mut scene = floor(rgb, Vec3::ZERO);
    scene.lights = vec![Light::Quad {
        corner: Vec3::new(2.0, -1.0, -1.0),
        edge_u: Vec3::new(0.0, 0.0, 2.0),
        edge_v: Vec3::new(0.0, 2.0, 0.0),
        radiance: Vec3::splat(5.0),
    }];
    let scene = Scene::with_surfaces(
        scene.name.clone(),
        scene.triangles.iter().map(|t| (*t, 0)).collect(),
        scene.materials.clone(),
        scene.lights.clone(),
        scene.camera,
        scene.surfaces.clone(),
    );
    let exact = RenderOptions::exact(SIDE, SIDE);
    let ray = centre(&scene, &RenderOptions { method: Method::Ray, spp: 4096, ..exact }, false);
    for wavefront in [false, true] {
        let beam = centre(&scene, &exact, wavefront);
        assert!(beam > 0.0 && (beam - ray).abs() < 0.02 * beam, "beam (wavefront {wavefront}) {beam}, rays {ray}");
    }
    let wave_ray = centre(&scene, &RenderOptions { method: Method::Ray, spp: 4096, ..exact }, true);
    assert!((wave_ray - ray).abs() < 1e-4 * ray, "the wavefront's rays {wave_ray}, the CPU's {ray}");
}

#[test]
fn the_wavefront_lights_a_normal_texture_as_the_cpu_does() {
    // Tilted 60° towards +x (world normal (√3/2, ½, 0)) under a uniform sky, a wall light that
    // reaches below the floor and a point light below the floor's plane but above the bent
    // normal's: the sky's faces and the wall light cross the floor's plane, the point light is
    // hidden.
    let bent = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
    let rgb = ((bent + Vec3::ONE) / 2.0 * 255.0).round().to_array().map(|v| v as u8);
    let mut scene = floor(rgb, Vec3::new(2.0, -0.5, 0.0));
    scene.lights.push(Light::Quad {
        corner: Vec3::new(2.0, -1.0, -1.0),
        edge_u: Vec3::new(0.0, 0.0, 2.0),
        edge_v: Vec3::new(0.0, 2.0, 0.0),
        radiance: Vec3::splat(5.0),
    });
    let mut scene = Scene::with_surfaces(
        scene.name.clone(),
        scene.triangles.iter().map(|t| (*t, 0)).collect(),
        scene.materials.clone(),
        scene.lights.clone(),
        scene.camera,
        scene.surfaces.clone(),
    );
    scene.environment = Environment::Constant(Vec3::splat(0.3));
    for method in [Method::Beam, Method::Ray] {
        let options = RenderOptions { method, spp: 16, ..RenderOptions::exact(SIDE, SIDE) };
        let (cpu, _) = render(&scene, &options, || {});
        let (wave, _) = render_queries(&scene, &options, &CpuBeams, || {}).expect("the CPU answers every query");
        let d = difference(&wave, &cpu).expect("one size");
        println!("{method:?}: PSNR {:.1} dB", d.psnr);
        assert!(d.psnr > 60.0, "{method:?}: PSNR {} dB", d.psnr);
        let centre = wave.pixels[(SIDE * SIDE / 2) as usize].x;
        assert!(centre > 0.0, "{method:?}: the centre is lit");
    }
}
