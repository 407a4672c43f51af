//! Caustics and nonlinear shadows by the two-pass method of 000 §9.2: beams from each point light
//! through every mirror and glass S-mesh face carry the light's flux; their texels find the
//! receiver points (pass 1), whose flux is gathered into an irradiance map (pass 2). A receiver the
//! beams do not reach lies in a nonlinear shadow. The ground truth traces photons from the light
//! through the same surfaces about the interpolated normals.

use super::atlas::BeamTexture;
use super::smesh::{SFace, SMesh};
use super::trace::{Beam, BeamJob, BeamRenderer, Degree, TEXELS, child_beams};
use crate::render::{DEPTH_EPS, IrradianceMap, dielectric, shading_eps};
use crate::scene::{Light, Material, Scene};
use beam_math::Ray;
use beam_math::glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use rayon::prelude::*;

/// What the caustic pass did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct CausticStats {
    /// Light beams rendered (reflection and refraction beams off S-mesh faces the lights see).
    pub beams: u64,
    /// Beam texels that carried flux to a diffuse receiver.
    pub texels_deposited: u64,
}

impl core::ops::Add for CausticStats {
    type Output = Self;

    fn add(self, other: Self) -> Self {
        Self { beams: self.beams + other.beams, texels_deposited: self.texels_deposited + other.texels_deposited }
    }
}

/// World size of an irradiance-map texel for `scene`: 1/256 of its bounding box's largest side.
#[must_use]
pub fn caustic_texel(scene: &Scene) -> f32 {
    scene.bounds().extent().max_element() / 256.0
}

/// A point light's position and intensity.
type PointLight = (Vec3, Vec3);

/// A point light, an S-mesh face it lights and the face's light beams (refracted ones marked `true`).
type LitFace<'a> = (PointLight, &'a SFace, Vec<(Beam, bool)>);

/// The point lights of `scene`.
fn point_lights(scene: &Scene) -> Vec<PointLight> {
    scene
        .lights
        .iter()
        .filter_map(|l| match *l {
            Light::Point { position, intensity } => Some((position, intensity)),
            _ => None,
        })
        .collect()
}

/// The point lights, the S mesh and an empty irradiance map of `scene`; `None` without point lights
/// or specular faces.
fn setup(scene: &Scene) -> Option<(Vec<PointLight>, SMesh, IrradianceMap)> {
    let lights = point_lights(scene);
    let smesh = SMesh::specular(scene);
    if lights.is_empty() || smesh.faces.is_empty() {
        return None;
    }
    Some((lights, smesh, IrradianceMap::new(scene, caustic_texel(scene))))
}

/// True when the segment from `p` (on triangle `prim`, offset by `eps` towards `to`) to `to` is
/// blocked.
fn blocked(scene: &Scene, prim: u32, p: Vec3, to: Vec3, eps: f32) -> bool {
    let n = scene.normal(prim);
    let side = if n.dot(to - p) > 0.0 { n } else { -n };
    let o = p + side * eps;
    scene.wide.any_hit(Ray::new(o, to - o), 1.0 - DEPTH_EPS)
}

/// Fresnel split of light along unit `d` meeting face `f` at barycentric `w`: the weights of its
/// reflection and its transmission (0 for mirrors; mirrors reflect their tint).
fn split(scene: &Scene, f: &SFace, w: Vec3, d: Vec3) -> (Vec3, f32) {
    let entering = d.dot(scene.normal(f.prim)) < 0.0;
    let n = if entering { f.normal_at(w) } else { -f.normal_at(w) };
    match scene.material(f.prim) {
        Material::Mirror { tint, .. } => (tint, 0.0),
        Material::Glass { ior } => match dielectric(d, n, ior, entering) {
            (fresnel, Some(_)) => (Vec3::splat(fresnel), 1.0 - fresnel),
            (_, None) => (Vec3::ONE, 0.0),
        },
        _ => (Vec3::ZERO, 0.0),
    }
}

/// Pass 1 and 2 by beams: for every point light and S-mesh face, the reflection and refraction
/// beams (S1 or S3, `texels` per side) from the light; every texel strictly inside the base carries
/// the flux `I·cosθ·A/r²` of its share `A` of the base (less what the Fresnel split sends the other
/// way), unless the light is blocked before the face; its ray's first hit, when diffuse, receives
/// it. Paths with a second specular bounce are not followed. `None` without point lights or
/// specular faces; an error when `renderer` fails. `texels` is taken within [`TEXELS`].
pub fn caustics_by_beams(
    scene: &Scene,
    degree: Degree,
    texels: u32,
    renderer: &dyn BeamRenderer,
) -> Result<Option<(IrradianceMap, CausticStats)>, String> {
    let texels = texels.clamp(*TEXELS.start(), *TEXELS.end());
    let Some((lights, smesh, empty)) = setup(scene) else { return Ok(None) };
    let eps = shading_eps(scene);
    // Per point light and face it lights: its reflection and refraction beams.
    let faces: Vec<LitFace<'_>> = lights
        .iter()
        .flat_map(|&l| smesh.faces.iter().map(move |f| (l, f)))
        .filter_map(|((light, intensity), f)| {
            let incoming = f.v.map(|v| (v - light).normalize_or_zero());
            let (reflected, refracted) = child_beams(scene, f, incoming, degree)?;
            let beams = [Some(reflected), refracted.flatten()].into_iter().flatten().zip([false, true]).collect();
            Some(((light, intensity), f, beams))
        })
        .collect();
    let mut map = empty.clone();
    let mut stats = CausticStats::default();
    // Batches of faces, so that the beams' textures stay within a few hundred MB.
    for batch in faces.chunks(512) {
        let jobs: Vec<BeamJob<'_>> = batch
            .iter()
            .flat_map(|(_, f, beams)| beams.iter().map(|(beam, _)| BeamJob { beam, size: texels, exclude: f.prim }))
            .collect();
        let mut textures = renderer.render_beams(scene, &jobs)?.into_iter();
        let work: Vec<_> = batch
            .iter()
            .map(|(l, f, beams)| (*l, *f, beams, textures.by_ref().take(beams.len()).collect::<Vec<_>>()))
            .collect();
        let (m, s) = work
            .par_iter()
            .fold(
                || (empty.clone(), CausticStats::default()),
                |(mut map, mut stats), (light, f, beams, textures)| {
                    // Whether the light reaches each texel's base point, shared by the face's beams.
                    let mut lit = vec![None; (texels * texels) as usize];
                    for ((beam, transmitted), tex) in beams.iter().zip(textures) {
                        stats.beams += 1;
                        deposit(scene, f, beam, tex, *light, *transmitted, eps, &mut lit, &mut map, &mut stats);
                    }
                    (map, stats)
                },
            )
            .reduce(
                || (empty.clone(), CausticStats::default()),
                |(mut a, sa), (b, sb)| {
                    a.merge(&b);
                    (a, sa + sb)
                },
            );
        map.merge(&m);
        stats = stats + s;
    }
    Ok(Some((map, stats)))
}

/// Splat the flux of one light beam's texels `tex` off face `f` (see [`caustics_by_beams`]);
/// `lit` caches per texel whether the light reaches its base point (shadow rays offset by `eps`).
#[allow(clippy::too_many_arguments)]
fn deposit(
    scene: &Scene,
    f: &SFace,
    beam: &Beam,
    tex: &BeamTexture,
    (light, intensity): PointLight,
    transmitted: bool,
    eps: f32,
    lit: &mut [Option<bool>],
    map: &mut IrradianceMap,
    stats: &mut CausticStats,
) {
    let n = scene.normal(f.prim);
    // Texels whose centre lies strictly inside the base: x + y + 1 ≤ size, n(n+1)/2 of them.
    let inside = u64::from(tex.size) * u64::from(tex.size + 1) / 2;
    let share = f.area() / inside as f32;
    for y in 0..tex.size {
        for x in 0..tex.size - y {
            let Some(hit) = tex.hits[(y * tex.size + x) as usize] else { continue };
            if !matches!(scene.material(hit.prim), Material::Diffuse { .. } | Material::Glossy { .. }) {
                continue;
            }
            let w = tex.barycentric(x, y);
            let base = f.v[0] * w.x + f.v[1] * w.y + f.v[2] * w.z;
            let to = base - light;
            let r2 = to.length_squared();
            let d = to / r2.sqrt();
            let (reflect, transmit) = split(scene, f, w, d);
            let weight = if transmitted { Vec3::splat(transmit) } else { reflect };
            if weight == Vec3::ZERO
                || !*lit[(y * tex.size + x) as usize].get_or_insert_with(|| !blocked(scene, f.prim, base, light, eps))
            {
                continue;
            }
            let ray = beam.ray_at(w);
            let flux = intensity * weight * (n.dot(d).abs() * share / r2);
            if map.splat(hit.prim, ray.at(hit.t), flux) {
                stats.texels_deposited += 1;
            }
        }
    }
}

/// The ground truth of [`caustics_by_beams`]: about `photons` photons from each point light, spread
/// over the S-mesh faces in proportion to the flux they receive and placed uniformly at random on
/// each face; each carries `I·cosθ·A/(r²·M)` of its face's `M` photons, is split by Fresnel about the
/// interpolated normal at its own point, and its reflected and refracted rays deposit on the first
/// surface they hit when it is diffuse (second specular bounces are not followed, as for beams).
#[must_use]
pub fn caustics_by_photons(scene: &Scene, photons: u64, seed: u64) -> Option<IrradianceMap> {
    let (lights, smesh, empty) = setup(scene)?;
    let eps = shading_eps(scene);
    let mut jobs = Vec::new();
    for &(light, intensity) in &lights {
        let share = |f: &SFace| {
            let c = (f.v[0] + f.v[1] + f.v[2]) / 3.0;
            let to = c - light;
            scene.normal(f.prim).dot(to).abs() / to.length().powi(3) * f.area()
        };
        let total: f32 = smesh.faces.iter().map(share).sum();
        for (i, f) in smesh.faces.iter().enumerate() {
            let m = (photons as f64 * f64::from(share(f) / total.max(f32::MIN_POSITIVE))).ceil() as u64;
            jobs.push((light, intensity, f, m, seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)));
        }
    }
    let map = jobs
        .par_iter()
        .fold(
            || empty.clone(),
            |mut map, &(light, intensity, f, m, seed)| {
                let mut rng = Pcg32::seed_from_u64(seed);
                let (area, n) = (f.area(), scene.normal(f.prim));
                for _ in 0..m {
                    let (mut s, mut t) = (rng.random::<f32>(), rng.random::<f32>());
                    if s + t > 1.0 {
                        (s, t) = (1.0 - s, 1.0 - t);
                    }
                    let w = Vec3::new(1.0 - s - t, s, t);
                    let p = f.v[0] * w.x + f.v[1] * w.y + f.v[2] * w.z;
                    let to = p - light;
                    let r2 = to.length_squared();
                    let d = to / r2.sqrt();
                    if blocked(scene, f.prim, p, light, eps) {
                        continue;
                    }
                    let flux = intensity * (n.dot(d).abs() * area / (r2 * m as f32));
                    let entering = d.dot(n) < 0.0;
                    let ns = if entering { f.normal_at(w) } else { -f.normal_at(w) };
                    let (reflect, transmit) = split(scene, f, w, d);
                    let side = if entering { n } else { -n };
                    let mut rays = vec![(Ray::new(p + side * eps, crate::render::reflect(d, ns)), reflect)];
                    if let (Material::Glass { ior }, true) = (scene.material(f.prim), transmit > 0.0) {
                        if let (_, Some(t)) = dielectric(d, ns, ior, entering) {
                            rays.push((Ray::new(p - side * eps, t), Vec3::splat(transmit)));
                        }
                    }
                    for (ray, weight) in rays {
                        if let Some(hit) = scene.wide.closest_hit(ray, f32::INFINITY) {
                            map.splat(hit.prim, ray.at(hit.t), flux * weight);
                        }
                    }
                }
                map
            },
        )
        .reduce(
            || empty.clone(),
            |mut a, b| {
                a.merge(&b);
                a
            },
        );
    Some(map)
}
