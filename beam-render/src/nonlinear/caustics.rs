//! Caustics and nonlinear shadows by the two-pass method of 000 §9.2: beams from each light
//! through every mirror and glass S-mesh face carry the light's flux; their texels find the
//! receiver points (pass 1), whose flux is gathered into an irradiance map (pass 2). A receiver the
//! beams do not reach lies in a nonlinear shadow. 000 traces from point lights; an area light is
//! taken as N × N stratified point emitters with cosine emission (as the glossy light volumes take
//! it, [`stratified`]; N = [`CAUSTIC_STRATA`] by default). The ground truth traces photons from the lights (from uniform
//! points over an area light's whole area) through the same surfaces about the interpolated normals.

use super::beam_tree::{Beam, Degree, child_beams};
use super::face::{Exclude, SFace};
use super::renderer::BeamRenderer;
use super::smesh::SMesh;
use super::texture::{BeamJob, BeamTexture, TEXELS};
use crate::BackendError;
use crate::glossy::{Emitter, area_point, stratified, whole};
use crate::irradiance_map::IrradianceMap;
use crate::specular::dielectric;
use crate::tolerance::{DEPTH_EPS, shading_eps};
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_scene::scene::{Light, Material, Scene};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use rayon::prelude::*;

/// Strata per side of an area light in the caustic pass, by default (`beam render
/// --caustic-strata`). Each of an area light's `k²` stratum emitters renders its beams with `1/k`
/// of the texels per side, so that it deposits as many texels as a point light; but every beam
/// costs its bounding triangles, so an area light's caustics cost about `k²` point lights'.
pub const CAUSTIC_STRATA: u32 = 2;

/// Most strata per side of an area light in the caustic pass.
pub const MAX_CAUSTIC_STRATA: u32 = 8;

/// What the caustic pass did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct CausticStats {
    /// Light beams rendered (reflection and refraction beams off S-mesh faces the emitters light).
    pub beams: u64,
    /// Beam texels that carried flux to a diffuse receiver.
    pub texels_deposited: u64,
    /// Wall-clock seconds of the caustic pass.
    pub seconds: f64,
}

impl core::ops::Add for CausticStats {
    type Output = Self;

    fn add(self, other: Self) -> Self {
        Self {
            beams: self.beams + other.beams,
            texels_deposited: self.texels_deposited + other.texels_deposited,
            seconds: self.seconds + other.seconds,
        }
    }
}

/// World size of an irradiance-map texel for `scene`: 1/256 of its bounding box's largest side.
#[must_use]
pub fn caustic_texel(scene: &Scene) -> f32 {
    scene.bounds().extent().max_element() / 256.0
}

/// An emitter, an S-mesh face it lights, what its beams skip and the face's light beams (refracted
/// ones marked `true`).
type LitFace<'a> = (Emitter, &'a SFace, Exclude<'a>, Vec<(Beam, bool)>);

/// The S mesh (`smesh`) and an empty irradiance map of `scene`; `None` without lights or specular
/// faces.
fn setup(scene: &Scene, smesh: SMesh) -> Option<(SMesh, IrradianceMap)> {
    if scene.lights.is_empty() || smesh.faces.is_empty() {
        return None;
    }
    Some((smesh, IrradianceMap::new(scene, caustic_texel(scene))))
}

/// True when emitter `e` sends no light to face `f` (the face lies wholly behind an area light).
fn behind(e: &Emitter, f: &SFace) -> bool {
    f.v.iter().all(|&v| e.falloff((v - e.position).normalize_or_zero()) <= 0.0)
}

/// True when the segment from `p` (on a surface of normal `n`, offset by `eps` towards `to`) to `to`
/// is blocked.
fn blocked(scene: &Scene, n: Vec3, p: Vec3, to: Vec3, eps: f32) -> bool {
    let side = if n.dot(to - p) > 0.0 { n } else { -n };
    let o = p + side * eps;
    scene.occluded(Ray::new(o, to - o), 1.0 - DEPTH_EPS)
}

/// Fresnel split of light along unit `d` meeting face `f` at barycentric `w`: the weights of its
/// reflection and its transmission (0 for mirrors; mirrors reflect their tint).
fn split(scene: &Scene, f: &SFace, w: Vec3, d: Vec3) -> (Vec3, f32) {
    let entering = d.dot(f.normal) < 0.0;
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

/// Pass 1 and 2 by beams: for every emitter (a point light, or one of an area light's `strata ×
/// strata` strata: [`stratified`]; none for `strata` 0) and S-mesh face in front of it, the
/// reflection and refraction beams (S1 or S3, `texels` per side, `texels / strata` for a stratum)
/// from the emitter; every texel strictly inside the base carries the flux `I(d)·cosθ·A/r²` of its
/// share `A` of the base (less what the Fresnel split sends the other way), unless the emitter is
/// blocked before the face; its ray's first hit, when diffuse, receives it. The faces are the
/// specular triangles themselves ([`SMesh::specular`]) whatever S mesh the eye's beams spawn from:
/// on a coarse S mesh each light beam stands for more of the surface, and at equal texels per beam
/// the irradiance map is coarser and noisier (on the mirror teapot the error outside the specular
/// surfaces grew 4.5×), while √(fine triangles) texels per side cost 7× the fine faces' pass (the
/// wide beams' bounding triangles). Paths with a second
/// specular bounce are not followed. `None` without lights or specular faces; an error when
/// `renderer` fails. `texels` is taken within [`TEXELS`], `strata` within
/// `0..=`[`MAX_CAUSTIC_STRATA`].
pub fn caustics_by_beams(
    scene: &Scene,
    degree: Degree,
    texels: u32,
    strata: u32,
    renderer: &dyn BeamRenderer,
) -> Result<Option<(IrradianceMap, CausticStats)>, BackendError> {
    let texels = texels.clamp(*TEXELS.start(), *TEXELS.end());
    let start = std::time::Instant::now();
    let Some((smesh, empty)) = setup(scene, SMesh::specular(scene)) else { return Ok(None) };
    let strata = strata.min(MAX_CAUSTIC_STRATA);
    let size = |e: &Emitter| if e.is_point() { texels } else { (texels / strata).max(*TEXELS.start()) };
    // A coarse S-mesh face stands for its patch of fine triangles: its beams get √patch times the
    // texels per side, so that the light deposits as many texels as through the fine faces.
    let size_under = |e: &Emitter, ex: &Exclude<'_>| {
        let k = (ex.patch.len().max(1) as f32).sqrt();
        ((size(e) as f32 * k).round() as u32).clamp(size(e), *TEXELS.end())
    };
    let eps = shading_eps(scene);
    // Per emitter and face it lights: its reflection and refraction beams.
    let emitters = stratified(scene, strata.max(1)).into_iter();
    let faces: Vec<LitFace<'_>> = emitters
        .filter(|e| strata > 0 || e.is_point())
        .flat_map(|e| smesh.faces.iter().enumerate().map(move |(i, f)| (e, i, f)))
        .filter(|(e, _, f)| !behind(e, f))
        .filter_map(|(e, i, f)| {
            let incoming = f.v.map(|v| (v - e.position).normalize_or_zero());
            let (reflected, refracted) = child_beams(scene, f, incoming, degree)?;
            let beams = [Some(reflected), refracted.flatten()].into_iter().flatten().zip([false, true]).collect();
            Some((e, f, smesh.exclude(i), beams))
        })
        .collect();
    let (mut map, mut stats) = (empty, CausticStats::default());
    // Batches of faces, so that the beams' textures stay within a few hundred MB.
    for batch in faces.chunks(512) {
        let jobs: Vec<BeamJob<'_>> = batch
            .iter()
            .flat_map(|(e, _, ex, beams)| {
                beams.iter().map(|(beam, _)| BeamJob { beam, size: size_under(e, ex), exclude: *ex })
            })
            .collect();
        let mut textures = renderer.render_beams(scene, &jobs)?.into_iter();
        let work: Vec<_> = batch
            .iter()
            .map(|(l, f, ex, beams)| {
                (*l, (*f, ex.thickness), beams, textures.by_ref().take(beams.len()).collect::<Vec<_>>())
            })
            .collect();
        // Per face, the flux its beams deposit, splatted in the faces' order: every process of a
        // render farm sums the same map. (Lists of deposits, not a map per chunk of faces: a map
        // cloned, filled and merged 128 times a batch cost more than the deposits themselves.)
        let per_face: Vec<_> = work
            .par_iter()
            .map(|(e, f, beams, textures)| {
                // Whether the emitter reaches each texel's base point, shared by the face's beams.
                let n = textures.first().map_or(0, |t| t.size as usize);
                let (mut lit, mut deposits) = (vec![None; n * n], Vec::new());
                for ((beam, transmitted), tex) in beams.iter().zip(textures) {
                    deposit(scene, *f, beam, tex, e, *transmitted, eps, &mut lit, &mut deposits);
                }
                deposits
            })
            .collect();
        stats.beams += work.iter().map(|w| w.2.len() as u64).sum::<u64>();
        for (prim, p, d, flux) in per_face.into_iter().flatten() {
            stats.texels_deposited += u64::from(map.splat(prim, p, d, flux));
        }
    }
    stats.seconds = start.elapsed().as_secs_f64();
    Ok(Some((map, stats)))
}

/// The flux of one light beam's texels `tex` off face `f` (with the thickness of the surface under
/// it; see [`caustics_by_beams`]), appended to `out` as (receiving triangle, point, direction of
/// travel, flux) to splat; `lit` caches per texel whether emitter `e` reaches its base point
/// (shadow rays offset by `eps`, plus the thickness).
fn deposit(
    scene: &Scene,
    (f, thickness): (&SFace, f32),
    beam: &Beam,
    tex: &BeamTexture,
    e: &Emitter,
    transmitted: bool,
    eps: f32,
    lit: &mut [Option<bool>],
    out: &mut Vec<(u32, Vec3, Vec3, Vec3)>,
) {
    let n = f.normal;
    // Texels whose centre lies strictly inside the base: x + y + 2 ≤ size, n(n−1)/2 of them (the
    // next diagonal's centres lie on the edge, where rays start on the neighbouring faces).
    let inside = u64::from(tex.size) * u64::from(tex.size - 1) / 2;
    let share = f.area() / inside as f32;
    for y in 0..tex.size - 1 {
        for x in 0..tex.size - 1 - y {
            let Some(hit) = tex.hits[(y * tex.size + x) as usize] else { continue };
            if !matches!(scene.material(hit.prim), Material::Diffuse { .. } | Material::Glossy { .. }) {
                continue;
            }
            let w = tex.barycentric(x, y);
            let base = f.v[0] * w.x + f.v[1] * w.y + f.v[2] * w.z;
            let to = base - e.position;
            let r2 = to.length_squared();
            let d = to / r2.sqrt();
            let (reflect, transmit) = split(scene, f, w, d);
            let weight = if transmitted { Vec3::splat(transmit) } else { reflect } * e.falloff(d);
            if weight == Vec3::ZERO
                || !*lit[(y * tex.size + x) as usize]
                    .get_or_insert_with(|| !blocked(scene, n, base, e.position, eps + thickness))
            {
                continue;
            }
            let ray = beam.ray_at(w);
            out.push((hit.prim, ray.at(hit.t), ray.direction, e.intensity * weight * (n.dot(d).abs() * share / r2)));
        }
    }
}

/// The ground truth of [`caustics_by_beams`]: about `photons` photons from each light, spread over
/// the specular triangles (the fine S mesh, [`SMesh::specular`], whatever S mesh the beams use) in proportion to the flux they receive (from the light's centre) and placed
/// uniformly at random on each face, each leaving a point light's position or a uniform random point
/// of an area light; each carries `I(d)·cosθ·A/(r²·M)` of its face's `M` photons (`I(d)` the
/// light's whole intensity `L·A_light·cosθ_light` for an area light), is split by Fresnel about the
/// interpolated normal at its own point, and its reflected and refracted rays deposit on the first
/// surface they hit when it is diffuse (second specular bounces are not followed, as for beams).
#[must_use]
pub fn caustics_by_photons(scene: &Scene, photons: u64, seed: u64) -> Option<IrradianceMap> {
    let (smesh, empty) = setup(scene, SMesh::specular(scene))?;
    let eps = shading_eps(scene);
    let mut jobs = Vec::new();
    for (li, light) in scene.lights.iter().enumerate() {
        let Some(e) = whole(scene, light, li as u32) else { continue };
        let share = |f: &SFace| {
            let c = (f.v[0] + f.v[1] + f.v[2]) / 3.0;
            let to = c - e.position;
            let falloff = if behind(&e, f) { 0.0 } else { e.falloff(to.normalize_or_zero()).max(1e-3) };
            f.normal.dot(to).abs() / to.length().powi(3) * f.area() * falloff
        };
        let shares: Vec<f32> = smesh.faces.iter().map(share).collect();
        let total: f32 = shares.iter().sum();
        for (i, (f, share)) in smesh.faces.iter().zip(shares).enumerate() {
            let m = (photons as f64 * f64::from(share / total.max(f32::MIN_POSITIVE))).ceil() as u64;
            let salt = (i as u64 + (li as u64) * smesh.faces.len() as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            jobs.push((light, e, f, m, seed ^ salt));
        }
    }
    // In a fixed order, so that every process of a render farm sums the same map.
    let map = crate::ordered::fold_in_order(
        &jobs,
        || empty.clone(),
        |mut map, &(light, e, f, m, seed)| {
            let mut rng = Pcg32::seed_from_u64(seed);
            let (area, n) = (f.area(), f.normal);
            for _ in 0..m {
                let (mut s, mut t) = (rng.random::<f32>(), rng.random::<f32>());
                if s + t > 1.0 {
                    (s, t) = (1.0 - s, 1.0 - t);
                }
                let w = Vec3::new(1.0 - s - t, s, t);
                let p = f.v[0] * w.x + f.v[1] * w.y + f.v[2] * w.z;
                let from = match light {
                    Light::Point { position, .. } => *position,
                    _ => area_point(light, rng.random(), rng.random()) + e.normal * eps,
                };
                let to = p - from;
                let r2 = to.length_squared();
                let d = to / r2.sqrt();
                if e.falloff(d) <= 0.0 || blocked(scene, n, p, from, eps) {
                    continue;
                }
                let flux = e.towards(d) * (n.dot(d).abs() * area / (r2 * m as f32));
                let entering = d.dot(n) < 0.0;
                let ns = if entering { f.normal_at(w) } else { -f.normal_at(w) };
                let (reflect, transmit) = split(scene, f, w, d);
                let side = if entering { n } else { -n };
                let mut rays = vec![(Ray::new(p + side * eps, crate::specular::reflect(d, ns)), reflect)];
                if let (Material::Glass { ior }, true) = (scene.material(f.prim), transmit > 0.0) {
                    if let (_, Some(t)) = dielectric(d, ns, ior, entering) {
                        rays.push((Ray::new(p - side * eps, t), Vec3::splat(transmit)));
                    }
                }
                for (ray, weight) in rays {
                    if let Some(hit) = scene.closest_hit(ray, f32::INFINITY) {
                        map.splat(hit.prim, ray.at(hit.t), ray.direction, flux * weight);
                    }
                }
            }
            map
        },
        |a, b| a.merge(&b),
    );
    Some(map)
}
