//! The rays the BVH properties trace: camera, shadow and diffuse rays over a mesh, seeded.

use crate::generate::{self, Rng64, uniform};
use beam_bvh::FlatBvh;
use beam_math::glam::Vec3;
use beam_math::{Aabb, Ray, Triangle};

/// Rays of the three kinds for one mesh.
pub struct RaySet {
    /// Camera rays: from an eye inside the scene's box and from one outside looking in.
    pub camera: Vec<Ray>,
    /// Shadow rays from camera hits to random points of a quad light under the top of the box, each
    /// with `t_max` just short of the light.
    pub shadow: Vec<(Ray, f32)>,
    /// Cosine-distributed bounces from camera hits.
    pub diffuse: Vec<Ray>,
    /// The quad light's centre and downward normal (for the PAH builders).
    pub light: (Vec3, Vec3),
    /// The outside eye (for the PAH builders).
    pub eye: Vec3,
}

/// The scene light (centre and edges): [`beam_scene::scene::Light::under_ceiling`] of a third of the
/// box's width.
#[must_use]
pub fn scene_light(bounds: Aabb) -> (Vec3, Vec3, Vec3) {
    match beam_scene::scene::Light::under_ceiling(bounds, 0.33, Vec3::ONE) {
        beam_scene::scene::Light::Quad { corner, edge_u, edge_v, .. } => {
            (corner + 0.5 * (edge_u + edge_v), edge_u, edge_v)
        }
        _ => unreachable!("under_ceiling is a quad"),
    }
}

/// Generate `n` rays of each kind, seeded; `bvh` only finds the camera hits to start from.
pub fn ray_set(triangles: &[Triangle], bvh: &FlatBvh, n: usize, seed: u64) -> RaySet {
    let mut rng = generate::rng(seed);
    let bounds = bvh.nodes.first().map_or(Aabb::new(Vec3::ZERO, Vec3::ONE), |r| r.bounds());
    let c = bounds.center();
    let e = bounds.extent();
    let inside = c + e * Vec3::new(0.11, 0.13, -0.07);
    let eye = c + e.length() * Vec3::new(0.6, 0.35, 0.9);
    let camera: Vec<Ray> = (0..n)
        .map(|i| {
            if i % 2 == 0 {
                Ray::new(inside, generate::unit(&mut rng))
            } else {
                let target = c + e
                    * 0.5
                    * Vec3::new(
                        uniform(&mut rng, -1.0, 1.0),
                        uniform(&mut rng, -1.0, 1.0),
                        uniform(&mut rng, -1.0, 1.0),
                    );
                Ray::new(eye, target - eye)
            }
        })
        .collect();
    let hits = bvh.closest_hits(triangles, &camera, f32::INFINITY);
    let (lc, lu, lv) = scene_light(bounds);
    let mut shadow = Vec::with_capacity(n);
    let mut diffuse = Vec::with_capacity(n);
    let eps = 1e-4 * e.length();
    let mut k = 0;
    while shadow.len() < n && k < 50 * n {
        let i = k % n;
        k += 1;
        let Some(h) = hits[i] else { continue };
        let ray = camera[i];
        let tri = &triangles[h.prim as usize];
        let mut normal = tri.scaled_normal().normalize_or_zero();
        if normal.dot(ray.direction) > 0.0 {
            normal = -normal;
        }
        let p = ray.at(h.t) + normal * eps;
        let target = lc + lu * uniform(&mut rng, -0.5, 0.5) + lv * uniform(&mut rng, -0.5, 0.5);
        shadow.push((Ray::new(p, target - p), 0.999));
        diffuse.push(Ray::new(p, cosine_direction(&mut rng, normal)));
    }
    // Meshes where few camera rays hit: fill with rays from the eyes.
    while shadow.len() < n {
        let r = camera[shadow.len() % n];
        shadow.push((r, 1.0));
        diffuse.push(r);
    }
    RaySet { camera, shadow, diffuse, light: (lc, Vec3::NEG_Y), eye }
}

fn cosine_direction(rng: &mut Rng64, n: Vec3) -> Vec3 {
    let (u1, u2) = (uniform(rng, 0.0, 1.0), uniform(rng, 0.0, 1.0));
    let r = u1.sqrt();
    let phi = std::f32::consts::TAU * u2;
    let t = n.any_orthonormal_vector();
    let b = n.cross(t);
    (t * r * phi.cos() + b * r * phi.sin() + n * (1.0 - u1).max(0.0).sqrt()).normalize()
}
