//! Built-in scenes of the glossy light volumes (002 Figs. 2, 3 and 13): a mirror ring casting the
//! cardioid, caustics under wavy water, and stained-glass windows of increasing roughness, each lit
//! by a point light.

use super::light::Light;
use super::material::Material;
use super::model::Scene;
use super::showcase::{GOLD, MIRROR, Tris, WHITE, add, camera, checker, materials, pool, wall};
use crate::mesh;
use beam_math::glam::Vec3;
use std::f32::consts::TAU;

/// The cardioid caustic (002 Fig. 2): a mirror ring of `segments × 2` triangles (inner surface,
/// normals inwards) on a white floor, lit from one side above its rim, so that its far inner wall
/// focuses the light into a cardioid on the floor inside the ring and its near wall casts a shadow.
#[must_use]
pub fn cardioid_ring(segments: u32) -> Scene {
    let mut tris = Tris::new();
    let size = 800.0;
    wall(
        &mut tris,
        Vec3::new(-size / 2.0, 0.0, -size / 2.0),
        Vec3::new(0.0, 0.0, size),
        Vec3::new(size, 0.0, 0.0),
        WHITE,
    );
    let (radius, height) = (120.0f32, 45.0f32);
    // ∂u × ∂v points to the axis: the reflecting side faces inwards.
    let ring = mesh::parametric(segments, 1, |u, v| {
        let phi = TAU * u;
        Vec3::new(radius * phi.cos(), height * v, radius * phi.sin())
    });
    add(&mut tris, &ring, MIRROR);
    let light = Light::Point { position: Vec3::new(-520.0, 260.0, 0.0), intensity: Vec3::splat(2.5e5) };
    let camera = camera(Vec3::new(40.0, 360.0, -260.0), Vec3::new(20.0, 0.0, 0.0), 45.0);
    Scene::new("cardioid-ring".into(), tris, materials(), vec![light], camera)
}

/// Caustics under wavy water (002 Fig. 3): a water surface (index 1.33) of `n × n × 2` triangles
/// over a white pool with a gold ball on its floor, a point light above.
#[must_use]
pub fn pool_caustics(n: u32) -> Scene {
    let mut tris = Tris::new();
    let (h, bed, rim) = (300.0f32, -150.0f32, 30.0f32);
    wall(&mut tris, Vec3::new(-h, bed, -h), Vec3::new(0.0, 0.0, 2.0 * h), Vec3::new(2.0 * h, 0.0, 0.0), WHITE);
    pool(&mut tris, n, (h, bed, rim), WHITE);
    add(&mut tris, &mesh::sphere(Vec3::new(70.0, bed + 45.0, 40.0), 45.0, 12, 24), GOLD);
    let light = Light::Point { position: Vec3::new(60.0, 650.0, -60.0), intensity: Vec3::splat(1.2e6) };
    let camera = camera(Vec3::new(0.0, 560.0, -470.0), Vec3::new(0.0, -110.0, 40.0), 45.0);
    Scene::new("pool-caustics".into(), tris, materials(), vec![light], camera)
}

/// Stained glass (002 Fig. 13): three windows of 3 × 4 coloured thin-glass panes in a dark wall,
/// roughness σ = 0, 0.05 and 0.15 rad from left to right, lit from behind by a point light, so that
/// their coloured light falls on the floor of the room in front, sharp to blurred; a white backdrop
/// behind the light shows through the panes.
#[must_use]
pub fn stained_glass() -> Scene {
    let mut tris = Tris::new();
    let mut materials = materials();
    let wall_material = materials.len() as u32;
    materials.push(Material::Diffuse { albedo: Vec3::splat(0.2) });
    let colours = [
        Vec3::new(0.9, 0.15, 0.1),
        Vec3::new(0.15, 0.35, 0.9),
        Vec3::new(0.95, 0.8, 0.15),
        Vec3::new(0.15, 0.75, 0.25),
        Vec3::new(0.8, 0.3, 0.85),
        Vec3::new(0.9, 0.9, 0.9),
    ];
    // The room: floor z ∈ [−700, 0] in front of the wall at z = 0, which faces −z.
    wall(&mut tris, Vec3::new(-700.0, 0.0, -700.0), Vec3::new(0.0, 0.0, 700.0), Vec3::new(1400.0, 0.0, 0.0), WHITE);
    let (bottom, top, width) = (120.0f32, 320.0f32, 150.0f32);
    let lefts = [-345.0f32, -75.0, 195.0];
    // The wall around the windows: strips between and around them.
    let mut x = -700.0;
    for left in lefts {
        wall(
            &mut tris,
            Vec3::new(x, 0.0, 0.0),
            Vec3::new(left - x, 0.0, 0.0),
            Vec3::new(0.0, 450.0, 0.0),
            wall_material,
        );
        wall(
            &mut tris,
            Vec3::new(left, 0.0, 0.0),
            Vec3::new(width, 0.0, 0.0),
            Vec3::new(0.0, bottom, 0.0),
            wall_material,
        );
        wall(
            &mut tris,
            Vec3::new(left, top, 0.0),
            Vec3::new(width, 0.0, 0.0),
            Vec3::new(0.0, 450.0 - top, 0.0),
            wall_material,
        );
        x = left + width;
    }
    wall(&mut tris, Vec3::new(x, 0.0, 0.0), Vec3::new(700.0 - x, 0.0, 0.0), Vec3::new(0.0, 450.0, 0.0), wall_material);
    for (w, (left, sigma)) in lefts.into_iter().zip([0.0f32, 0.05, 0.15]).enumerate() {
        let first = materials.len() as u32;
        materials.extend(colours.iter().map(|&tint| Material::ThinGlass { tint, sigma }));
        let (cols, rows) = (3u32, 4u32);
        for j in 0..rows {
            for i in 0..cols {
                let corner = Vec3::new(
                    left + width * i as f32 / cols as f32,
                    bottom + (top - bottom) * j as f32 / rows as f32,
                    0.0,
                );
                let m = first + (i + j * cols + w as u32) % colours.len() as u32;
                let (eu, ev) =
                    (Vec3::new(width / cols as f32, 0.0, 0.0), Vec3::new(0.0, (top - bottom) / rows as f32, 0.0));
                checker(&mut tris, corner, eu, ev, 1, (m, m));
            }
        }
    }
    // A white backdrop behind the light, seen through the panes.
    wall(&mut tris, Vec3::new(-900.0, 0.0, 1100.0), Vec3::new(1800.0, 0.0, 0.0), Vec3::new(0.0, 450.0, 0.0), WHITE);
    let light = Light::Point { position: Vec3::new(0.0, 900.0, 450.0), intensity: Vec3::splat(4.0e6) };
    let camera = camera(Vec3::new(0.0, 330.0, -950.0), Vec3::new(0.0, 140.0, -150.0), 50.0);
    Scene::new("stained-glass".into(), tris, materials, vec![light], camera)
}
