//! Build a BVH over a triangle soup given as vertex triples and trace rays through it: the nearest
//! hit (triangle, distance, barycentric weights) and a shadow query (any hit before a distance).
//!
//! `cargo run --release -p beam-bvh --example trace`

use beam_bvh::beam_math::glam::Vec3;
use beam_bvh::beam_math::{Ray, Triangle};
use beam_bvh::{BuildOptions, FlatBvh};

fn main() {
    // Your mesh as a flat list of vertices, three per triangle: here a 16 × 16 grid of quads at
    // z = 0 and one quad above it, at z = 1, covering the grid's middle.
    let mut vertices: Vec<[f32; 3]> = Vec::new();
    let mut quad = |x0: f32, y0: f32, x1: f32, y1: f32, z: f32| {
        vertices.extend([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y0, z], [x1, y1, z], [x0, y1, z]]);
    };
    for i in 0..16 {
        for j in 0..16 {
            quad(i as f32, j as f32, i as f32 + 1.0, j as f32 + 1.0, 0.0);
        }
    }
    quad(6.0, 6.0, 10.0, 10.0, 1.0);
    let triangles: Vec<Triangle> =
        vertices.chunks_exact(3).map(|v| Triangle::new(v[0].into(), v[1].into(), v[2].into())).collect();

    // Binned SAH; degenerate triangles would be left out and counted.
    let bvh = FlatBvh::build(&triangles, &BuildOptions::sah());
    println!("{} triangles, {} nodes, {} degenerate", triangles.len(), bvh.nodes.len(), bvh.degenerate);

    // Nearest hits of rays looking down: the raised quad hides the grid's middle.
    for (x, y) in [(2.3, 2.6), (8.3, 7.9), (20.0, 20.0)] {
        let ray = Ray::new(Vec3::new(x, y, 5.0), Vec3::NEG_Z);
        match bvh.closest_hit(&triangles, ray, f32::INFINITY) {
            Some(h) => {
                println!("ray down at ({x}, {y}): triangle {} at t = {} (u = {:.3}, v = {:.3})", h.prim, h.t, h.u, h.v)
            }
            None => println!("ray down at ({x}, {y}): no hit"),
        }
    }

    // A shadow query: is the light at (8, 8, 4) visible from the grid point (8.3, 8.6, 0)? The
    // segment is `origin + t·direction`, t in (0, 1): occluders between the two points only.
    let (point, light) = (Vec3::new(8.3, 8.6, 0.0), Vec3::new(8.0, 8.0, 4.0));
    let shadow = Ray::new(point + Vec3::Z * 1e-4, light - point);
    println!("light visible from {point}: {}", !bvh.any_hit(&triangles, shadow, 1.0));

    // Many rays at once, in parallel.
    let rays: Vec<Ray> =
        (0..64).map(|k| Ray::new(Vec3::new(0.25 * k as f32 + 0.1, 8.2, 5.0), Vec3::new(0.0, 0.0, -1.0))).collect();
    let hits = bvh.closest_hits(&triangles, &rays, f32::INFINITY);
    let raised = hits.iter().flatten().filter(|h| h.t < 4.5).count();
    println!("{} of {} rays hit, {raised} of them the raised quad", hits.iter().flatten().count(), rays.len());
}
