//! Built-in scenes, so that the default job needs no files.

use super::camera::Camera;
use super::foliage;
use super::light::Light;
use super::light_volumes;
use super::material::{Bump, Material};
use super::model::Scene;
use super::names::GENERATED;
use super::showcase;
use crate::error::SceneError;
use crate::mesh::{self, Mesh};
use beam_math::Triangle;
use beam_math::glam::{Mat3, Vec3};

/// A built-in scene by name.
pub fn builtin(name: &str) -> Result<Scene, SceneError> {
    match name {
        "cornell" => Ok(cornell(false, false)),
        "mirror-glass" => Ok(cornell(true, false)),
        "cornell-point" => Ok(cornell(false, true)),
        "mirror-glass-coarse" => {
            // The mirror sphere at a coarse S-mesh resolution (8 × 16), where S1's kinks show.
            Ok(coarse_mirror(cornell(true, false)))
        }
        "facing-mirrors" => Ok(showcase::facing_mirrors(12)),
        "facing-mirrors-coarse" => Ok(showcase::facing_mirrors(4)),
        "glass-lens" => Ok(showcase::glass_lens(8)),
        "glass-lens-coarse" => Ok(showcase::glass_lens(3)),
        "mirror-teapot" => Ok(showcase::mirror_teapot(24, 16)),
        "mirror-teapot-coarse" => Ok(showcase::mirror_teapot(10, 16)),
        "wavy-lake" => Ok(showcase::wavy_lake(24)),
        "wavy-lake-coarse" => Ok(showcase::wavy_lake(8)),
        "bumpy-mirror" => Ok(bumpy(cornell(true, false))),
        "cardioid-ring" => Ok(light_volumes::cardioid_ring(40)),
        "pool-caustics" => Ok(light_volumes::pool_caustics(20)),
        "stained-glass" => Ok(light_volumes::stained_glass()),
        "foliage" => Ok(foliage::foliage(foliage::LEAVES, 1)),
        // The generated cases of `beam bench softshadow --suite`, by the same names.
        name if GENERATED.contains(&name) => match super::suite::case(name)? {
            super::suite::Case::Built(scene) => Ok(*scene),
            super::suite::Case::Absent(_) => Err(SceneError::UnknownScene { name: name.to_string() }),
        },
        _ => Err(SceneError::UnknownScene { name: name.to_string() }),
    }
}

/// A procedural built-in with its specular surfaces (the S mesh) at resolution `n` (quads per mirror
/// side, lens rings, teapot profile steps, water quads per side; 2 to 256).
pub fn builtin_with_smesh(name: &str, n: u32) -> Result<Scene, SceneError> {
    if !(2..=256).contains(&n) {
        return Err(SceneError::SmeshResolution { resolution: n });
    }
    match name {
        "facing-mirrors" => Ok(showcase::facing_mirrors(n)),
        "glass-lens" => Ok(showcase::glass_lens(n)),
        "mirror-teapot" => Ok(showcase::mirror_teapot(n, 16)),
        "wavy-lake" => Ok(showcase::wavy_lake(n)),
        _ => Err(SceneError::NotProcedural { name: name.to_string() }),
    }
}

fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Mesh {
    Mesh { positions: vec![a, b, c, d], indices: vec![[0, 1, 2], [0, 2, 3]] }
}

/// `scene` with its mirror triangles replaced by an 8 × 16 sphere of the same centre and radius.
fn coarse_mirror(scene: Scene) -> Scene {
    let mirror = |m: &Material| matches!(m, Material::Mirror { .. });
    let mut tris: Vec<(Triangle, u32)> = Vec::new();
    let mut mirror_material = None;
    for (t, &m) in scene.triangles.iter().zip(&scene.material_of) {
        if mirror(&scene.materials[m as usize]) {
            mirror_material = Some(m);
        } else {
            tris.push((*t, m));
        }
    }
    if let Some(m) = mirror_material {
        let sphere = mesh::sphere(Vec3::new(185.0, 90.0, 170.0), 90.0, 8, 16);
        tris.extend(sphere.triangles().into_iter().map(|t| (t, m)));
    }
    Scene::new("mirror-glass-coarse".into(), tris, scene.materials, scene.lights, scene.camera)
}

/// `scene` with its mirrors bump-mapped (000 §6.3): rays tilted by up to 0.06 rad by ripples of
/// wavelength 40.
fn bumpy(mut scene: Scene) -> Scene {
    for m in &mut scene.materials {
        if let Material::Mirror { bump, .. } = m {
            *bump = Bump { delta: 0.06, wavelength: 40.0 };
        }
    }
    scene.name = "bumpy-mirror".into();
    scene
}

/// A box of size `size` standing on the floor at `center`, turned by `angle` degrees about y.
fn turned_box(center: Vec3, size: Vec3, angle: f32) -> Mesh {
    let mut m = mesh::cuboid(-0.5 * size, 0.5 * size);
    let r = Mat3::from_rotation_y(angle.to_radians());
    for p in &mut m.positions {
        *p = center + r * *p + Vec3::Y * 0.5 * size.y;
    }
    m
}

/// The Cornell box (the classic 555-unit room with its 130 × 105 ceiling light), with its two boxes,
/// or with a mirror sphere and a glass sphere instead (`spheres`); with `point_light`, lit by a point
/// light under the ceiling's centre instead (hard shadows, 001 §4.2).
fn cornell(spheres: bool, point_light: bool) -> Scene {
    let s = 555.0;
    let white = Material::Diffuse { albedo: Vec3::splat(0.73) };
    let red = Material::Diffuse { albedo: Vec3::new(0.65, 0.05, 0.05) };
    let green = Material::Diffuse { albedo: Vec3::new(0.12, 0.45, 0.15) };
    let emitter = Material::Emissive { radiance: Vec3::splat(15.0) };
    let mirror = Material::Mirror { tint: Vec3::splat(0.95), bump: Bump::NONE };
    let glass = Material::Glass { ior: 1.5 };
    let materials = vec![white, red, green, emitter, mirror, glass];
    let mut tris: Vec<(Triangle, u32)> = Vec::new();
    let mut add = |m: &Mesh, mat: u32| tris.extend(m.triangles().into_iter().map(|t| (t, mat)));
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    // Room, faces towards the inside (the camera looks along +z from z < 0).
    add(&quad(p(0.0, 0.0, 0.0), p(0.0, 0.0, s), p(s, 0.0, s), p(s, 0.0, 0.0)), 0); // floor
    add(&quad(p(0.0, s, 0.0), p(s, s, 0.0), p(s, s, s), p(0.0, s, s)), 0); // ceiling
    add(&quad(p(0.0, 0.0, s), p(0.0, s, s), p(s, s, s), p(s, 0.0, s)), 0); // back
    add(&quad(p(s, 0.0, 0.0), p(s, 0.0, s), p(s, s, s), p(s, s, 0.0)), 1); // x = s, the camera's left: red
    add(&quad(p(0.0, 0.0, 0.0), p(0.0, s, 0.0), p(0.0, s, s), p(0.0, 0.0, s)), 2); // x = 0, the camera's right: green
    // Light: 130 × 105 below the ceiling, facing down.
    let (corner, eu, ev) = (p(213.0, 548.7, 227.0), p(130.0, 0.0, 0.0), p(0.0, 0.0, 105.0));
    add(&quad(corner, corner + ev, corner + eu + ev, corner + eu), 3);
    if spheres {
        add(&mesh::sphere(p(185.0, 90.0, 170.0), 90.0, 24, 48), 4);
        add(&mesh::sphere(p(370.0, 90.0, 350.0), 90.0, 24, 48), 5);
    } else {
        add(&turned_box(p(185.0, 0.0, 169.0), p(165.0, 165.0, 165.0), -18.0), 0);
        add(&turned_box(p(368.0, 0.0, 351.0), p(165.0, 330.0, 165.0), 15.0), 0);
    }
    let lights = vec![if point_light {
        // As bright straight below as the quad light: intensity = radiance × area.
        Light::Point { position: p(278.0, 500.0, 279.5), intensity: Vec3::splat(15.0 * 130.0 * 105.0) }
    } else {
        Light::Quad { corner, edge_u: eu, edge_v: ev, radiance: Vec3::splat(15.0) }
    }];
    let camera = Camera {
        position: p(278.0, 273.0, -800.0),
        target: p(278.0, 273.0, 0.0),
        up: Vec3::Y,
        fov_y: 39.3,
        width: 512,
        height: 512,
    };
    let name = match (spheres, point_light) {
        (true, _) => "mirror-glass",
        (false, true) => "cornell-point",
        (false, false) => "cornell",
    };
    Scene::new(name.into(), tris, materials, lights, camera)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cornell_light_faces_down_and_room_is_closed_enough() {
        let s = builtin("cornell").unwrap();
        assert_eq!(s.lights[0].normal(), Vec3::NEG_Y);
        assert!((s.lights[0].area() - 130.0 * 105.0).abs() < 1e-2);
        assert_eq!(s.stats.degenerate, 0);
        let g = builtin("mirror-glass").unwrap();
        assert!(g.stats.degenerate > 0, "the UV spheres' pole triangles are filtered and counted");
        assert!(builtin("nope").err().unwrap().to_string().contains("cornell"));
    }
}
