//! Built-in scenes of curved mirrors and glass for the nonlinear beam tracer (000 Figs. 1 and 15 and
//! a two-mirror multi-bounce scene), built from procedural meshes whose resolution is the S mesh's.

use super::camera::Camera;
use super::light::Light;
use super::material::{Bump, Material};
use super::model::Scene;
use crate::mesh::{self, Mesh};
use beam_math::Triangle;
use beam_math::glam::{Mat3, Vec3};
use std::f32::consts::{PI, TAU};

/// Triangles with a material index each, as [`Scene::new`] takes them.
pub(super) type Tris = Vec<(Triangle, u32)>;

pub(super) fn add(tris: &mut Tris, m: &Mesh, material: u32) {
    tris.extend(m.triangles().into_iter().map(|t| (t, material)));
}

/// A checkerboard of `n × n` squares on the rectangle `corner + [0, 1]·eu + [0, 1]·ev`, alternating
/// materials `a` and `b`.
pub(super) fn checker(tris: &mut Tris, corner: Vec3, eu: Vec3, ev: Vec3, n: u32, (a, b): (u32, u32)) {
    for j in 0..n {
        for i in 0..n {
            let p = |di: u32, dj: u32| corner + eu * ((i + di) as f32 / n as f32) + ev * ((j + dj) as f32 / n as f32);
            let m = if (i + j) % 2 == 0 { a } else { b };
            tris.push((Triangle { v: [p(0, 0), p(1, 0), p(1, 1)] }, m));
            tris.push((Triangle { v: [p(0, 0), p(1, 1), p(0, 1)] }, m));
        }
    }
}

/// A one-material rectangle `corner + [0, 1]·eu + [0, 1]·ev` (a wall).
pub(super) fn wall(tris: &mut Tris, corner: Vec3, eu: Vec3, ev: Vec3, material: u32) {
    checker(tris, corner, eu, ev, 1, (material, material));
}

/// A checkered floor of `n × n` white and dark squares over the square of side `size` at `corner`
/// (spanning +x and +z).
fn floor(tris: &mut Tris, corner: Vec3, size: f32, n: u32) {
    checker(tris, corner, Vec3::new(0.0, 0.0, size), Vec3::new(size, 0.0, 0.0), n, (WHITE, DARK));
}

/// A 512² camera at `position` looking at `target`, up +y, vertical field of view `fov_y` degrees.
pub(super) fn camera(position: Vec3, target: Vec3, fov_y: f32) -> Camera {
    Camera { position, target, up: Vec3::Y, fov_y, width: 512, height: 512 }
}

/// The materials every showcase scene shares, by index.
pub(super) const WHITE: u32 = 0;
pub(super) const DARK: u32 = 1;
pub(super) const RED: u32 = 2;
pub(super) const GREEN: u32 = 3;
pub(super) const GOLD: u32 = 4;
pub(super) const MIRROR: u32 = 5;
pub(super) const GLASS: u32 = 6;
pub(super) const WATER: u32 = 7;

pub(super) fn materials() -> Vec<Material> {
    vec![
        Material::Diffuse { albedo: Vec3::splat(0.75) },
        Material::Diffuse { albedo: Vec3::new(0.08, 0.1, 0.3) },
        Material::Diffuse { albedo: Vec3::new(0.7, 0.1, 0.08) },
        Material::Diffuse { albedo: Vec3::new(0.12, 0.5, 0.15) },
        Material::Diffuse { albedo: Vec3::new(0.8, 0.55, 0.1) },
        Material::Mirror { tint: Vec3::splat(0.95), bump: Bump::NONE },
        Material::Glass { ior: 1.5 },
        Material::Glass { ior: 1.33 },
    ]
}

/// A square light of side `size` at height `y` over `(x, z)`, facing down.
fn ceiling_light(x: f32, y: f32, z: f32, size: f32) -> Light {
    let h = 0.5 * size;
    Light::Quad {
        corner: Vec3::new(x - h, y, z - h),
        edge_u: Vec3::new(size, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, size),
        radiance: Vec3::splat(12.0),
    }
}

/// A square patch of the sphere of radius `radius` about `centre`, around direction `axis`, spanning
/// `±half` radians each way, `n × n` quads.
fn sphere_patch(centre: Vec3, radius: f32, axis: Vec3, half: f32, n: u32) -> Mesh {
    let t1 = axis.any_orthonormal_vector();
    let t2 = axis.cross(t1);
    mesh::parametric(n, n, |u, v| {
        let (a, b) = ((2.0 * u - 1.0) * half, (2.0 * v - 1.0) * half);
        centre + radius * (axis + a.tan() * t1 + b.tan() * t2).normalize()
    })
}

/// Two concave spherical mirrors facing each other across a checkered floor, a gold ball and a red
/// box between them: the eye sees reflections of reflections (beam-tree levels 2 and more). `n`
/// quads per mirror side.
#[must_use]
pub fn facing_mirrors(n: u32) -> Scene {
    let mut tris = Tris::new();
    floor(&mut tris, Vec3::new(-400.0, 0.0, -400.0), 800.0, 8);
    wall(&mut tris, Vec3::new(-400.0, 0.0, 400.0), Vec3::new(800.0, 0.0, 0.0), Vec3::new(0.0, 500.0, 0.0), GREEN);
    let radius = 1400.0;
    for side in [-1.0f32, 1.0] {
        // The mirror at x = 260·side, its sphere's centre across the room: concave towards it.
        let centre = Vec3::new(-side * (radius - 260.0), 160.0, 0.0);
        add(&mut tris, &sphere_patch(centre, radius, Vec3::X * side, 0.1, n), MIRROR);
    }
    add(&mut tris, &mesh::sphere(Vec3::new(20.0, 60.0, -40.0), 60.0, 16, 32), GOLD);
    add(&mut tris, &mesh::cuboid(Vec3::new(-150.0, 0.0, 60.0), Vec3::new(-70.0, 160.0, 140.0)), RED);
    let camera = camera(Vec3::new(230.0, 230.0, -170.0), Vec3::new(-260.0, 140.0, 0.0), 50.0);
    Scene::new("facing-mirrors".into(), tris, materials(), vec![ceiling_light(0.0, 600.0, -100.0, 200.0)], camera)
}

/// A biconvex glass lens (000 Fig. 15) standing before a checkered wall: caps of curvature radius
/// 300 over an aperture of radius 120, joined by a rim band 20 thick (a sharp crease); `n` rings and
/// `4n` segments per cap.
#[must_use]
pub fn glass_lens(n: u32) -> Scene {
    let mut tris = Tris::new();
    floor(&mut tris, Vec3::new(-500.0, 0.0, -600.0), 1000.0, 10);
    checker(
        &mut tris,
        Vec3::new(-400.0, 0.0, 300.0),
        Vec3::new(800.0, 0.0, 0.0),
        Vec3::new(0.0, 500.0, 0.0),
        10,
        (RED, WHITE),
    );
    let (r, a, half_band, y) = (300.0f32, 120.0f32, 10.0f32, 160.0f32);
    let sag = |rho: f32| (r * r - rho * rho).sqrt() - (r * r - a * a).sqrt();
    for side in [-1.0f32, 1.0] {
        let cap = mesh::parametric(4 * n, n, |u, v| {
            // Outward normals (∂u × ∂v): the angle runs against `side`.
            let (rho, phi) = (a * v, -TAU * u * side);
            Vec3::new(rho * phi.cos(), y + rho * phi.sin(), side * (half_band + sag(rho)))
        });
        add(&mut tris, &cap, GLASS);
    }
    let band = mesh::parametric(4 * n, 1, |u, v| {
        let phi = TAU * u;
        Vec3::new(a * phi.cos(), y + a * phi.sin(), half_band * (2.0 * v - 1.0))
    });
    add(&mut tris, &band, GLASS);
    add(&mut tris, &mesh::cuboid(Vec3::new(-15.0, 0.0, -15.0), Vec3::new(15.0, y - a, 15.0)), DARK);
    add(&mut tris, &mesh::sphere(Vec3::new(-230.0, 50.0, 120.0), 50.0, 16, 32), GOLD);
    let camera = camera(Vec3::new(60.0, 200.0, -560.0), Vec3::new(0.0, 160.0, 0.0), 40.0);
    Scene::new("glass-lens".into(), tris, materials(), vec![ceiling_light(0.0, 650.0, -250.0, 250.0)], camera)
}

/// A mirror teapot among objects (000 Fig. 1): a procedural teapot (body and lid revolved from the
/// Utah teapot's profile, a torus handle, a tapered curved spout, a knob) on a checkered floor with
/// coloured walls, a gold ball, a glass ball and a box; `n` sets the mirror's S-mesh resolution and
/// `ball` the gold ball's (`ball × 2·ball` quads; the scene-triangle axis of 000 Fig. 10).
#[must_use]
pub fn mirror_teapot(n: u32, ball: u32) -> Scene {
    let mut tris = Tris::new();
    floor(&mut tris, Vec3::new(-400.0, 0.0, -400.0), 800.0, 8);
    let (up, along_x, along_z) = (Vec3::new(0.0, 500.0, 0.0), Vec3::new(800.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 800.0));
    wall(&mut tris, Vec3::new(-400.0, 0.0, 400.0), along_x, up, WHITE);
    wall(&mut tris, Vec3::new(-400.0, 0.0, -400.0), up, along_z, RED);
    wall(&mut tris, Vec3::new(400.0, 0.0, -400.0), along_z, up, GREEN);
    add(&mut tris, &teapot(Vec3::ZERO, 100.0, n), MIRROR);
    add(&mut tris, &mesh::sphere(Vec3::new(-230.0, 60.0, 60.0), 60.0, ball, 2 * ball), GOLD);
    add(&mut tris, &mesh::sphere(Vec3::new(190.0, 55.0, -130.0), 55.0, 16, 32), GLASS);
    add(&mut tris, &mesh::cuboid(Vec3::new(120.0, 0.0, 150.0), Vec3::new(240.0, 120.0, 270.0)), RED);
    let camera = camera(Vec3::new(-60.0, 280.0, -620.0), Vec3::new(0.0, 90.0, 0.0), 42.0);
    Scene::new("mirror-teapot".into(), tris, materials(), vec![ceiling_light(0.0, 499.0, -50.0, 220.0)], camera)
}

/// A teapot of body radius ≈ `size` standing on `base`: `n` profile steps and `2n` segments.
fn teapot(base: Vec3, size: f32, n: u32) -> Mesh {
    // (radius, height) along the Utah teapot's body and lid profiles, in body radii (the body is 1.5
    // wide at its widest in the original's units of 2).
    let body = [(0.0, 0.0), (0.75, 0.0), (0.95, 0.12), (1.0, 0.45), (0.9, 0.85), (0.7, 1.05), (0.65, 1.05)];
    let lid = [(0.65, 1.05), (0.6, 1.12), (0.35, 1.2), (0.08, 1.28), (0.0, 1.32)];
    let revolve = |profile: &[(f32, f32)]| {
        let at = |t: f32| {
            // Catmull-Rom through the profile points.
            let x = t * (profile.len() - 1) as f32;
            let i = (x.floor() as usize).min(profile.len() - 2);
            let f = x - i as f32;
            let p = |k: isize| {
                let (r, h) = profile[(i as isize + k).clamp(0, profile.len() as isize - 1) as usize];
                Vec3::new(r, h, 0.0)
            };
            let (p0, p1, p2, p3) = (p(-1), p(0), p(1), p(2));
            0.5 * (2.0 * p1
                + (p2 - p0) * f
                + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * f * f
                + (3.0 * p1 - p0 - 3.0 * p2 + p3) * f * f * f)
        };
        mesh::parametric(2 * n, n, move |u, v| {
            let q = at(1.0 - v);
            let phi = TAU * u;
            base + size * Vec3::new(q.x * phi.cos(), q.y, q.x * phi.sin())
        })
    };
    let mut m = revolve(&body);
    m.append(&revolve(&lid));
    // Handle: half a torus in the x–y plane on the −x side.
    let handle = mesh::parametric(n, n / 2 + 2, |u, v| {
        let (a, b) = (PI * (0.5 + u), TAU * v);
        let ring = Vec3::new(-0.95 + 0.38 * a.cos(), 0.6 + 0.38 * a.sin(), 0.0);
        let outward = Vec3::new(a.cos(), a.sin(), 0.0);
        base + size * (ring + 0.07 * (b.cos() * outward + b.sin() * Vec3::Z))
    });
    m.append(&handle);
    // Spout: a tube along a quadratic curve on the +x side, narrowing towards its mouth.
    let spout = mesh::parametric(n / 2 + 2, n, |u, v| {
        let (p0, p1, p2) = (Vec3::new(0.85, 0.35, 0.0), Vec3::new(1.45, 0.4, 0.0), Vec3::new(1.6, 1.05, 0.0));
        let c = p0 * (1.0 - u) * (1.0 - u) + 2.0 * p1 * u * (1.0 - u) + p2 * u * u;
        let tangent = (2.0 * (p1 - p0) * (1.0 - u) + 2.0 * (p2 - p1) * u).normalize();
        let side = tangent.cross(Vec3::Z);
        let radius = 0.16 - 0.08 * u;
        let b = -TAU * v;
        base + size * (c + radius * (b.cos() * side + b.sin() * Vec3::Z))
    });
    m.append(&spout);
    let r = Mat3::from_rotation_y(0.35);
    for p in &mut m.positions {
        *p = base + r * (*p - base);
    }
    m
}

/// A pool of half-width `h` from `bed` up to `rim`: four walls of `material` and, on top, a wavy
/// water surface ([`wave`]) of `n × n × 2` triangles.
pub(super) fn pool(tris: &mut Tris, n: u32, (h, bed, rim): (f32, f32, f32), material: u32) {
    for (corner, along) in [
        (Vec3::new(-h, bed, -h), Vec3::new(2.0 * h, 0.0, 0.0)),
        (Vec3::new(h, bed, -h), Vec3::new(0.0, 0.0, 2.0 * h)),
        (Vec3::new(h, bed, h), Vec3::new(-2.0 * h, 0.0, 0.0)),
        (Vec3::new(-h, bed, h), Vec3::new(0.0, 0.0, -2.0 * h)),
    ] {
        wall(tris, corner, along, Vec3::new(0.0, rim - bed, 0.0), material);
    }
    // u along z and v along x, so that ∂u × ∂v points up, out of the water.
    let water = mesh::parametric(n, n, |u, v| {
        let (x, z) = (h * (2.0 * v - 1.0), h * (2.0 * u - 1.0));
        Vec3::new(x, wave(x, z), z)
    });
    add(tris, &water, WATER);
}

/// The height of the wavy lake's surface over `(x, z)`: a sum of three sinusoids.
pub(super) fn wave(x: f32, z: f32) -> f32 {
    7.0 * (0.021 * x + 0.4).sin() + 5.0 * (0.027 * z - 0.013 * x).sin() + 3.0 * (0.043 * (x + z) + 1.1).sin()
}

/// A wavy lake (000 Fig. 13): water of index 1.33 whose surface is a sum of sinusoids over `n × n`
/// quads, in a walled basin with a checkered bed; a gold ball under the water, a red box and a flat
/// "bird" above it; lit by a point light, so that the bed shows caustics and the bird's shadow
/// through the water.
#[must_use]
pub fn wavy_lake(n: u32) -> Scene {
    let mut tris = Tris::new();
    let (h, bed, rim) = (300.0f32, -150.0f32, 30.0f32);
    floor(&mut tris, Vec3::new(-h, bed, -h), 2.0 * h, 6);
    pool(&mut tris, n, (h, bed, rim), GREEN);
    add(&mut tris, &mesh::sphere(Vec3::new(70.0, -95.0, 40.0), 45.0, 12, 24), GOLD);
    add(&mut tris, &mesh::cuboid(Vec3::new(-220.0, 60.0, 120.0), Vec3::new(-140.0, 140.0, 200.0)), RED);
    add(&mut tris, &mesh::cuboid(Vec3::new(-90.0, 230.0, -80.0), Vec3::new(30.0, 238.0, -30.0)), WHITE);
    let light = Light::Point { position: Vec3::new(60.0, 650.0, -60.0), intensity: Vec3::splat(1.2e6) };
    let camera = camera(Vec3::new(0.0, 560.0, -470.0), Vec3::new(0.0, -110.0, 40.0), 45.0);
    Scene::new("wavy-lake".into(), tris, materials(), vec![light], camera)
}
