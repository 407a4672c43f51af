//! The built-in `foliage` scene: a procedural tree of thousands of small leaves over a ground plane,
//! under a quad area light — the hardest case for exact soft shadows (001 §5.1's plant): every
//! shadow beam from the ground under the crown is split at the edges of many leaves.

use super::camera::Camera;
use super::light::Light;
use super::material::Material;
use super::model::Scene;
use beam_math::Triangle;
use beam_math::glam::{Quat, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// Leaves of the built-in `foliage` scene (two triangles each).
pub const LEAVES: u32 = 4000;

/// Half the side of the square ground plane (y = 0, centred on the trunk).
pub const GROUND: f32 = 12.0;

/// Height of the quad light's plane.
pub const LIGHT_HEIGHT: f32 = 10.0;

/// Radiance of the light (1.2 × 1.2 at height 10: about 0.5 sRGB on the lit ground).
const RADIANCE: f32 = 150.0;

/// A square prism of half-width `r` from `a` to `b` (its four sides, no caps): a trunk or a branch.
fn prism(a: Vec3, b: Vec3, r: f32) -> Vec<Triangle> {
    let axis = (b - a).normalize();
    let u = axis.any_orthonormal_vector() * r;
    let v = axis.cross(u);
    let corners = [u + v, -u + v, -u - v, u - v];
    let mut tris = Vec::with_capacity(8);
    for i in 0..4 {
        let (c0, c1) = (corners[i], corners[(i + 1) % 4]);
        tris.push(Triangle { v: [a + c0, a + c1, b + c1] });
        tris.push(Triangle { v: [a + c0, b + c1, b + c0] });
    }
    tris
}

/// A diamond-shaped leaf centred at `c`: `length` along the unit `along`, `width` across it, in the
/// plane of normal `n` (unit, orthogonal to `along`); two triangles sharing the long diagonal.
fn leaf(c: Vec3, along: Vec3, n: Vec3, length: f32, width: f32) -> [Triangle; 2] {
    let (l, w) = (0.5 * length * along, 0.5 * width * n.cross(along));
    let (base, tip) = (c - l, c + l);
    [Triangle { v: [base, c + w, tip] }, Triangle { v: [base, tip, c - w] }]
}

/// A uniformly random unit vector.
fn unit(rng: &mut Pcg32) -> Vec3 {
    let z = rng.random_range(-1.0f32..1.0);
    let phi = rng.random_range(0.0..std::f32::consts::TAU);
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), z, s * phi.sin())
}

/// A uniformly random point of the unit ball.
fn in_ball(rng: &mut Pcg32) -> Vec3 {
    unit(rng) * rng.random::<f32>().cbrt()
}

/// A tree of `leaves` leaves (seeded by `seed`) on a 24 × 24 ground plane, under a 1.2 × 1.2 quad
/// light at height 10 that is off to the side, so that the crown's soft shadow falls beside the
/// trunk where the camera sees it. The trunk rises 2.6 units from the origin; eight branches leave
/// its top upwards and outwards, and the leaves (0.3 long, 0.14 wide, random orientations) are
/// scattered in balls of radius 0.7 around random points of the branches' outer two thirds.
#[must_use]
pub fn foliage(leaves: u32, seed: u64) -> Scene {
    let ground = Material::Diffuse { albedo: Vec3::splat(0.7) };
    let bark = Material::Diffuse { albedo: Vec3::new(0.35, 0.22, 0.12) };
    let foliage = Material::Diffuse { albedo: Vec3::new(0.18, 0.45, 0.12) };
    let emitter = Material::Emissive { radiance: Vec3::splat(RADIANCE) };
    let materials = vec![ground, bark, foliage, emitter];
    let mut tris: Vec<(Triangle, u32)> = Vec::new();
    let p = Vec3::new;
    // Ground, facing up.
    let g = GROUND;
    let (a, b, c, d) = (p(-g, 0.0, -g), p(-g, 0.0, g), p(g, 0.0, g), p(g, 0.0, -g));
    tris.extend([Triangle { v: [a, b, c] }, Triangle { v: [a, c, d] }].map(|t| (t, 0)));
    // Trunk and branches.
    let mut rng = Pcg32::seed_from_u64(seed);
    let top = p(0.0, 2.6, 0.0);
    tris.extend(prism(Vec3::ZERO, top, 0.15).into_iter().map(|t| (t, 1)));
    let branches: Vec<(Vec3, Vec3)> = (0..8)
        .map(|i| {
            let azimuth = (i as f32 + rng.random_range(-0.3..0.3)) * std::f32::consts::TAU / 8.0;
            let elevation = rng.random_range(0.35f32..0.9);
            let dir = p(elevation.cos() * azimuth.cos(), elevation.sin(), elevation.cos() * azimuth.sin());
            let start = top - Vec3::Y * rng.random_range(0.0..0.6);
            (start, start + dir * rng.random_range(1.6..2.4))
        })
        .collect();
    for &(s, e) in &branches {
        tris.extend(prism(s, e, 0.05).into_iter().map(|t| (t, 1)));
    }
    // Leaves around the branches.
    for i in 0..leaves {
        let (s, e) = branches[i as usize % branches.len()];
        let center = s.lerp(e, rng.random_range(0.33..1.0)) + 0.7 * in_ball(&mut rng);
        let n = unit(&mut rng);
        let along = Quat::from_axis_angle(n, rng.random_range(0.0..std::f32::consts::TAU)) * n.any_orthonormal_vector();
        tris.extend(leaf(center, along, n, 0.3, 0.14).map(|t| (t, 2)));
    }
    // Light: 1.2 × 1.2 at height 10, off to +x, facing down (edge_u × edge_v = −y).
    let (corner, eu, ev) = (p(2.4, LIGHT_HEIGHT, -0.6), p(1.2, 0.0, 0.0), p(0.0, 0.0, 1.2));
    tris.extend(
        [
            Triangle { v: [corner, corner + ev, corner + eu + ev] },
            Triangle { v: [corner, corner + eu + ev, corner + eu] },
        ]
        .map(|t| (t, 3)),
    );
    let lights = vec![Light::Quad { corner, edge_u: eu, edge_v: ev, radiance: Vec3::splat(RADIANCE) }];
    let camera = Camera {
        position: p(5.0, 6.5, 12.0),
        target: p(-1.0, 1.8, 0.0),
        up: Vec3::Y,
        fov_y: 45.0,
        width: 512,
        height: 512,
    };
    Scene::new("foliage".into(), tris, materials, lights, camera)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leaves_lie_between_ground_and_light() {
        let s = foliage(LEAVES, 1);
        assert_eq!(s.stats.degenerate, 0);
        let leaves: Vec<&Triangle> =
            s.triangles.iter().zip(&s.material_of).filter(|&(_, &m)| m == 2).map(|(t, _)| t).collect();
        assert_eq!(leaves.len(), 2 * LEAVES as usize);
        assert!((8_000..8_200).contains(&s.stats.triangles), "{} triangles", s.stats.triangles);
        for t in &leaves {
            for v in t.v {
                assert!(v.y > 0.5 && v.y < LIGHT_HEIGHT - 4.0, "leaf vertex {v} not between ground and light");
                assert!(v.x.abs() < GROUND && v.z.abs() < GROUND);
            }
        }
    }

    #[test]
    fn seeded_and_deterministic() {
        let (a, b) = (foliage(200, 7), foliage(200, 7));
        assert_eq!(a.triangles, b.triangles);
        assert_ne!(a.triangles, foliage(200, 8).triangles);
    }
}
