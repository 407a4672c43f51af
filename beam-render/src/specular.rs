//! The specular bounce: mirror reflection, Snell's refraction and Schlick's Fresnel split, and the
//! rays a mirror or glass point sends on (Whitted), shared by every renderer and reference.

use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_math::nonlinear::perturb;
use beam_scene::scene::{Material, Scene};

/// Deepest mirror/glass recursion.
pub const MAX_DEPTH: u32 = 6;

/// The rays a mirror or glass triangle `prim` sends back along light arriving at point `p` along
/// unit direction `d`, with their weights: the reflection about the interpolated (Phong) normal
/// (tilted by a mirror's bump map; times its tint), and through glass the refraction too, the two
/// split by Fresnel (reflection alone under total internal reflection); through a thin pane, the ray
/// itself, tinted. Origins are offset by `eps` off the surface. `None` for other materials.
#[must_use]
pub fn specular_rays(scene: &Scene, eps: f32, prim: u32, p: Vec3, d: Vec3) -> Option<[Option<(Ray, Vec3)>; 2]> {
    let geometric = scene.normal(prim);
    let entering = geometric.dot(d) < 0.0;
    let n = if entering { geometric } else { -geometric };
    let s = scene.shading_normal(prim, p) * n.dot(geometric).signum();
    match scene.material(prim) {
        Material::Mirror { tint, bump } => {
            let mut r = reflect(d, s);
            if bump.delta > 0.0 {
                let tri = &scene.triangles[prim as usize];
                let u = (tri.v[1] - tri.v[0]).normalize_or_zero();
                r = perturb(r.normalize(), n, u, bump.tilt(tri, n, p), bump.delta);
            }
            Some([Some((Ray::new(p + n * eps, r), tint)), None])
        }
        Material::Glass { ior } => {
            let reflected = Ray::new(p + n * eps, reflect(d, s));
            Some(match dielectric(d, s, ior, entering) {
                (fresnel, Some(t)) => [
                    Some((reflected, Vec3::splat(fresnel))),
                    Some((Ray::new(p - n * eps, t), Vec3::splat(1.0 - fresnel))),
                ],
                (_, None) => [Some((reflected, Vec3::ONE)), None],
            })
        }
        Material::ThinGlass { tint, .. } => Some([Some((Ray::new(p - n * eps, d), tint)), None]),
        _ => None,
    }
}

/// Mirror reflection of direction `d` about unit normal `n`.
#[must_use]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Snell's law: the direction refracted from unit direction `d` through unit normal `n` (facing
/// against `d`) with relative index `eta = n₁/n₂`; `None` under total internal reflection.
#[must_use]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -n.dot(d);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| eta * d + (eta * cos_i - k.sqrt()) * n)
}

/// A smooth dielectric of index `ior` met by unit direction `d` at unit normal `n` (facing against
/// `d`), from outside when `entering`: Schlick's Fresnel reflectance and the refracted direction
/// (reflectance 1 and `None` under total internal reflection).
#[must_use]
pub fn dielectric(d: Vec3, n: Vec3, ior: f32, entering: bool) -> (f32, Option<Vec3>) {
    let eta = if entering { 1.0 / ior } else { ior };
    match refract(d, n, eta) {
        Some(t) => {
            let r0 = ((1.0 - ior) / (1.0 + ior)).powi(2);
            let cos = if entering { -n.dot(d) } else { -t.dot(n) };
            (r0 + (1.0 - r0) * (1.0 - cos).powi(5), Some(t))
        }
        None => (1.0, None),
    }
}
