//! Regions of the image left to primary rays (their eye beams would not pay: sub-pixel triangles)
//! trace one ray through each pixel's centre, and a stratified ray in each quarter of a pixel that
//! an edge may cross: a floor of 45,000 triangles, each under half a pixel, meets a wall of two.

use beam_cpu::render::render;
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_render::image::Image;
use beam_render::options::RenderOptions;
use beam_scene::scene::{Camera, Light, Material, Scene};

/// A floor of `n × n` quads over `[−2, 2]²` (material 0) before a wall of two triangles (material
/// 1), under a small area light.
fn floor_and_wall(n: usize) -> Scene {
    let mut triangles = Vec::new();
    let at = |i: usize| -2.0 + 4.0 * i as f32 / n as f32;
    for i in 0..n {
        for j in 0..n {
            let p = |a: usize, b: usize| Vec3::new(at(a), 0.0, at(b));
            let (a, b, c, d) = (p(i, j), p(i, j + 1), p(i + 1, j + 1), p(i + 1, j));
            triangles.push((Triangle::new(a, b, c), 0));
            triangles.push((Triangle::new(a, c, d), 0));
        }
    }
    let w = |x: f32, y: f32| Vec3::new(x, y, -2.0);
    triangles.push((Triangle::new(w(-2.0, 0.0), w(2.0, 0.0), w(2.0, 3.0)), 1));
    triangles.push((Triangle::new(w(-2.0, 0.0), w(2.0, 3.0), w(-2.0, 3.0)), 1));
    let materials =
        vec![Material::Diffuse { albedo: Vec3::splat(0.7) }, Material::Diffuse { albedo: Vec3::new(0.8, 0.4, 0.3) }];
    let light = Light::Quad {
        corner: Vec3::new(-0.3, 2.5, -0.3),
        edge_u: Vec3::new(0.6, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 0.6),
        radiance: Vec3::splat(20.0),
    };
    let camera = Camera {
        position: Vec3::new(0.0, 2.0, 3.5),
        target: Vec3::new(0.0, 0.5, -1.0),
        up: Vec3::Y,
        fov_y: 50.0,
        width: 64,
        height: 64,
    };
    Scene::new("floor and wall".into(), triangles, materials, vec![light], camera)
}

/// Root-mean-square difference of two images, over the mean of the second.
fn relative_rmse(a: &Image, b: &Image) -> f32 {
    let n = a.pixels.len() as f32;
    let mse = a.pixels.iter().zip(&b.pixels).map(|(p, q)| (*p - *q).length_squared()).sum::<f32>() / n;
    let mean = b.pixels.iter().map(|p| p.length()).sum::<f32>() / n;
    mse.sqrt() / mean
}

#[test]
fn ray_regions_sample_edges_finely_and_the_rest_once() {
    let scene = floor_and_wall(150);
    // Exact shadows, and 8 × 8 primary rays a pixel, each shaded where it hits.
    let (reference, _) = render(&scene, &RenderOptions { primary_spp: 64, ..RenderOptions::exact(64, 64) }, || {});
    let budgeted = RenderOptions { spp: 64, primary_beams: true, exact: false, ..RenderOptions::exact(64, 64) };
    let (image, stats) = render(&scene, &budgeted, || {});
    assert!(stats.ray_pixels >= 64 * 32, "the floor's regions go to rays: {} pixels", stats.ray_pixels);
    // A centre a pixel (and a ring around each region), up to four more where an edge may pass:
    // the floor's triangles are one smooth stretch, so few pixels take them. Along the edge, a
    // quarter-pixel sliver of floor or wall is shaded at the neighbour's point of its stretch.
    let rays_per_pixel = stats.camera_rays as f64 / stats.ray_pixels as f64;
    assert!((1.0..2.0).contains(&rays_per_pixel), "{rays_per_pixel} rays a pixel");
    assert!(stats.lent_fragments > 0, "slivers shaded at their neighbours' points");
    // The same render with primary rays instead of eye beams: one through every pixel's centre,
    // whose edges alias, and 2 × 2 stratified ones a pixel everywhere, each fragment shaded.
    let centres = RenderOptions { primary_beams: false, primary_spp: 1, ..budgeted };
    let (aliased, _) = render(&scene, &centres, || {});
    let (four, _) = render(&scene, &RenderOptions { primary_spp: 4, ..centres }, || {});
    let error = relative_rmse(&image, &reference);
    let (aliased_error, four_error) = (relative_rmse(&aliased, &reference), relative_rmse(&four, &reference));
    eprintln!("{rays_per_pixel:.2} rays a pixel: relative RMSE {error}; centres {aliased_error}, 2 × 2 {four_error}");
    assert!(error < 0.85 * aliased_error, "edges sampled finely: {error} against {aliased_error} by centres");
    assert!(error < 1.05 * four_error, "as close as 2 × 2 rays everywhere: {error} against {four_error}");
    // Exact eye beams everywhere shade every fragment at its own point.
    let (_, exact) = render(&scene, &RenderOptions { primary_beams: true, ..RenderOptions::exact(64, 64) }, || {});
    assert!(exact.fragments > exact.shade_points && exact.lent_fragments == 0, "{exact:?}");
}
