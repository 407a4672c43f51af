//! Caustics light the side of a thin surface they arrive on, not the other: a one-sided panel
//! standing before the Cornell box's mirror and glass spheres takes their caustic on the face
//! towards them, and its face towards the camera stays dark, by caustic beams (000 §9.2) and by
//! their photon reference alike, whichever way the panel's normal points.

use beam_cpu::nonlinear::CpuBeams;
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_render::irradiance_map::IrradianceMap;
use beam_render::nonlinear::{CAUSTIC_STRATA, Degree, caustics_by_beams, caustics_by_photons};
use beam_scene::scene::{self, Material, Scene};

/// `mirror-glass-coarse` with a diffuse panel (two triangles, normal `+z` or, `flipped`, `−z`)
/// at `z = 40`, between the camera (`z < 0`) and the spheres; the panel's triangles.
fn with_panel(flipped: bool) -> (Scene, [u32; 2]) {
    let base = scene::builtin("mirror-glass-coarse").expect("a built-in");
    let mut materials = base.materials.clone();
    let panel = materials.len() as u32;
    materials.push(Material::Diffuse { albedo: Vec3::splat(0.8) });
    let mut triangles: Vec<(Triangle, u32)> =
        base.triangles.iter().copied().zip(base.material_of.iter().copied()).collect();
    let p = |x: f32, y: f32| Vec3::new(x, y, 40.0);
    let (a, b, c, d) = (p(40.0, 0.0), p(330.0, 0.0), p(330.0, 240.0), p(40.0, 240.0));
    let first = triangles.len() as u32;
    if flipped {
        triangles.extend([(Triangle::new(a, c, b), panel), (Triangle::new(a, d, c), panel)]);
    } else {
        triangles.extend([(Triangle::new(a, b, c), panel), (Triangle::new(a, c, d), panel)]);
    }
    let mut scene = Scene::new("panel".into(), triangles, materials, base.lights.clone(), base.camera);
    scene.smesh = base.smesh.clone();
    (scene, [first, first + 1])
}

/// The caustic irradiance `map` holds on `panel` over a grid of its points, seen by a ray along
/// `d`.
fn seen(scene: &Scene, map: &IrradianceMap, panel: [u32; 2], d: Vec3) -> f32 {
    let mut sum = 0.0;
    for prim in panel {
        let t = scene.triangles[prim as usize];
        for i in 0..16 {
            for j in 0..16 - i {
                let (u, v) = ((i as f32 + 0.3) / 16.0, (j as f32 + 0.3) / 16.0);
                sum += map.irradiance(prim, t.v[0] + (t.v[1] - t.v[0]) * u + (t.v[2] - t.v[0]) * v, d).element_sum();
            }
        }
    }
    sum
}

#[test]
fn caustics_light_only_the_side_they_arrive_on() {
    for flipped in [false, true] {
        let (scene, panel) = with_panel(flipped);
        let by_beams = caustics_by_beams(&scene, Degree::S1, 16, CAUSTIC_STRATA, &CpuBeams)
            .expect("the CPU renders every beam")
            .expect("the spheres cast caustics")
            .0;
        let by_photons = caustics_by_photons(&scene, 200_000, 7).expect("the spheres cast caustics");
        for (name, map) in [("beams", &by_beams), ("photons", &by_photons)] {
            // Towards the spheres the panel faces +z: rays from there travel along −z.
            let (lit, dark) = (seen(&scene, map, panel, Vec3::NEG_Z), seen(&scene, map, panel, Vec3::Z));
            assert!(lit > 0.0, "{name}, flipped {flipped}: no caustic on the side towards the spheres");
            assert_eq!(dark, 0.0, "{name}, flipped {flipped}: {dark} on the side towards the camera (lit {lit})");
        }
    }
}
