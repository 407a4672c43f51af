//! Build a scene in code (no files) and render it with exact soft shadows: a floor, a floating
//! square occluder and a square area light above it, shaded by shadow beams (001) so that the
//! penumbra has no noise; then the same image by 16 shadow rays per pixel, for comparison.
//!
//! `cargo run --release -p beam-cpu --example soft_shadows` (writes `soft_shadows.png`)

use beam_cpu::render::{difference, render};
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_render::options::{Method, RenderOptions};
use beam_scene::scene::{Camera, Light, Material, Scene};
use std::path::Path;

/// The two triangles of the parallelogram `corner + s·u + t·v`, with material `m`.
fn quad(corner: Vec3, u: Vec3, v: Vec3, m: u32) -> [(Triangle, u32); 2] {
    [(Triangle::new(corner, corner + u, corner + u + v), m), (Triangle::new(corner, corner + u + v, corner + v), m)]
}

fn main() -> Result<(), beam_cpu::RenderError> {
    let white = Material::Diffuse { albedo: Vec3::splat(0.8) };
    let red = Material::Diffuse { albedo: Vec3::new(0.8, 0.2, 0.2) };
    let mut triangles = Vec::new();
    // Floor (material 0) and an occluder (material 1) one unit above it, facing up.
    triangles.extend(quad(Vec3::new(-4.0, 0.0, 4.0), Vec3::new(8.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -8.0), 0));
    triangles.extend(quad(Vec3::new(-0.5, 1.0, 0.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), 1));
    // A 1 × 1 light at height 3, emitting downwards (the side of edge_u × edge_v).
    let light = Light::Quad {
        corner: Vec3::new(-0.5, 3.0, -0.5),
        edge_u: Vec3::new(1.0, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 1.0),
        radiance: Vec3::splat(10.0),
    };
    let camera = Camera {
        position: Vec3::new(0.0, 5.0, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 45.0,
        width: 256,
        height: 256,
    };
    let scene = Scene::new("in code".into(), triangles, vec![white, red], vec![light], camera);

    let exact = RenderOptions::exact(256, 256);
    let (image, stats) = render(&scene, &exact, || {});
    image.save_png(Path::new("soft_shadows.png"))?;
    println!(
        "exact soft shadows: {:.3} s, {} shadow beams, {:.1} pieces per beam; wrote soft_shadows.png",
        stats.seconds,
        stats.shadow_beams,
        stats.pieces as f64 / stats.shadow_beams.max(1) as f64
    );

    let rays = RenderOptions { method: Method::Ray, spp: 16, ..exact };
    let (noisy, stats) = render(&scene, &rays, || {});
    let d = difference(&noisy, &image)?;
    println!("16 shadow rays per pixel: {:.3} s, {:.1} dB from the exact image", stats.seconds, d.psnr);
    Ok(())
}
