//! Backward beam construction (002 §3.1): from each point emitter (a point light, or a stratum of
//! an area light: see emitters.rs), through every scatterer triangle it lights, the three light
//! rays through the triangle's vertices, reflected or refracted about the interpolated vertex
//! normals into a triplet of scattered vectors (a warped volume) carrying the flux `Φs = I·Ω` of the
//! light's solid angle through the triangle (`I` the emitter's intensity towards it); and a
//! negative shadow beam (the light rays themselves) behind every scatterer triangle for
//! first-order shadows.

use super::emitters::{Emitter, emitters, sub_triangles};
use crate::specular::{dielectric, reflect};
use crate::tolerance::{DEPTH_EPS, shading_eps};
use beam_math::glam::Vec3;
use beam_math::glossy::{LightBeam, solid_angle};
use beam_math::{Ray, Triangle};
use beam_scene::scene::{Material, Scene};
use rayon::prelude::*;

/// How a scatterer turns the light (002 §1.2: specular micro-facet materials).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scatter {
    /// About the normal (mirrors, glossy reflectors, and glass's Fresnel reflection).
    Reflect,
    /// Into a dense medium by Snell's law (glass, water: one interface).
    Refract {
        /// Index of refraction.
        ior: f32,
    },
    /// Straight through a thin pane.
    Transmit,
}

/// What a scatterer material does: the beams it makes (kind, tint and micro-facet standard
/// deviation, radians); empty for receivers and emitters. Glass makes a refracted and a reflected
/// beam, their flux split by Fresnel (the tint here is 1: [`trace_light_beams`] applies it).
#[must_use]
pub fn scatterings(material: &Material) -> Vec<(Scatter, Vec3, f32)> {
    match *material {
        Material::Mirror { tint, .. } => vec![(Scatter::Reflect, tint, 0.0)],
        Material::Glass { ior } => vec![(Scatter::Refract { ior }, Vec3::ONE, 0.0), (Scatter::Reflect, Vec3::ONE, 0.0)],
        Material::ThinGlass { tint, sigma } => vec![(Scatter::Transmit, tint, sigma)],
        Material::Glossy { albedo, variance } => vec![(Scatter::Reflect, albedo, variance.max(0.0).sqrt())],
        Material::Diffuse { .. } | Material::Emissive { .. } => Vec::new(),
    }
}

/// True when light scattered by `material` is traced by light beams (it is not a receiver).
#[must_use]
pub fn is_scatterer(material: &Material) -> bool {
    !scatterings(material).is_empty()
}

/// One light volume: a scattered beam, or a negative shadow beam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlossyBeam {
    /// Scatterer vertices, unit scattered (or, for a shadow beam, light) directions, and
    /// `Φs/I = Ω`, the light's solid angle through the scatterer.
    pub beam: LightBeam,
    /// Radiant intensity of the emitter towards the scatterer (the mean over its three vertices)
    /// times the scatterer's tint and Fresnel weight (per channel); the emitter's intensity for a
    /// shadow beam.
    pub power: Vec3,
    /// Micro-facet standard deviation of the scatter angle (radians); 0: specular.
    pub sigma: f32,
    /// Index of its emitter among the scene's [`emitters`].
    pub light: u32,
    /// A negative shadow beam: removes the light's direct irradiance where it reaches.
    pub shadow: bool,
}

/// Unit vertex normals of scatterer `prim`: the scene's smooth normals where it has them (mirrors,
/// glass), else the geometric normal.
fn vertex_normals(scene: &Scene, prim: u32) -> [Vec3; 3] {
    scene.smooth_normals.get(&prim).copied().unwrap_or([scene.normal(prim); 3])
}

/// The light beams of `scene` (002 §3.1, in parallel over scatterer triangles): for every emitter
/// (point light, or stratum of an area light: [`emitters`]) and every scatterer triangle, a shadow
/// beam always, and its scattered beams when the light reaches its front (thin panes: either side),
/// a curved triangle (vertex normals apart) split into `subdivide²` sub-triangles whose vertex
/// normals interpolate its own (the micro-polygon step of 002 §4.5: the beams then follow the
/// smooth surface the normals stand for). Beams are clipped to the part of their scatterer that the
/// light reaches (shadow rays from the light; sub-triangles across a shadow's edge halved
/// `LIT_DEPTH` times), which 002 leaves out. Degenerate triangles (no solid angle, or a vertex at
/// the light) are skipped and counted.
#[must_use]
pub fn trace_light_beams(scene: &Scene, subdivide: u32) -> (Vec<GlossyBeam>, u64) {
    let lights = emitters(scene);
    let scatterers: Vec<u32> =
        (0..scene.triangles.len() as u32).filter(|&p| is_scatterer(&scene.material(p))).collect();
    let per: Vec<(Vec<GlossyBeam>, u64)> = scatterers
        .par_iter()
        .map(|&prim| {
            let mut out = Vec::new();
            let mut skipped = 0;
            for (li, light) in lights.iter().enumerate() {
                match beams_of(scene, prim, light, li as u32, subdivide.max(1)) {
                    Some(b) => out.extend(b),
                    None => skipped += 1,
                }
            }
            (out, skipped)
        })
        .collect();
    let skipped = per.iter().map(|p| p.1).sum();
    (per.into_iter().flat_map(|p| p.0).collect(), skipped)
}

/// How many times a sub-triangle that the light reaches in part is halved along its edges.
const LIT_DEPTH: u32 = 3;

/// The parts of the (sub-)triangle `corners` (barycentric in its scatterer) that the light
/// reaches, by `lit`: whole when it reaches its three vertices and its centroid, dropped when it
/// reaches none of them, else split at its edge midpoints into four, `depth` more times (a part
/// at the last level kept when the light reaches its centroid).
fn lit_parts(corners: [Vec3; 3], depth: u32, lit: &impl Fn(Vec3) -> bool, out: &mut Vec<[Vec3; 3]>) {
    let [a, b, c] = corners;
    let centroid = lit((a + b + c) / 3.0);
    let count = corners.iter().filter(|&&w| lit(w)).count() + usize::from(centroid);
    if count == 4 || (depth == 0 && centroid) {
        out.push(corners);
    } else if count > 0 && depth > 0 {
        let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
        for part in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
            lit_parts(part, depth - 1, lit, out);
        }
    }
}

/// The beams of scatterer `prim` lit by `emitter` (number `index`); `None` when degenerate.
fn beams_of(scene: &Scene, prim: u32, emitter: &Emitter, index: u32, k: u32) -> Option<Vec<GlossyBeam>> {
    let (light, intensity) = (emitter.position, emitter.intensity);
    let tri: Triangle = scene.triangles[prim as usize];
    let omega = solid_angle(light, &tri);
    let [a, b, c] = tri.v.map(|v| (v - light).try_normalize());
    if !(omega > 0.0) || !omega.is_finite() {
        return None;
    }
    let shadow = GlossyBeam {
        beam: LightBeam { origins: tri.v, dirs: [a?, b?, c?], flux: omega },
        power: intensity,
        sigma: 0.0,
        light: index,
        shadow: true,
    };
    let mut out = vec![shadow];
    let material = scene.material(prim);
    let g = scene.normal(prim);
    let centroid = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
    let front = g.dot(centroid - light) < 0.0;
    if !front && !matches!(material, Material::ThinGlass { .. }) {
        return Some(out);
    }
    // Vertex normals against the incoming light; a flat triangle (normals within 1.4e-3 rad) is not split.
    let normals = vertex_normals(scene, prim).map(|n| if front { n } else { -n });
    let flat = normals.iter().all(|n| n.dot(normals[0]) > 0.999_999);
    let at = |w: Vec3| tri.v[0] * w.x + tri.v[1] * w.y + tri.v[2] * w.z;
    // Whether the light reaches the scatterer's point at barycentric `w` (offset to the lit side).
    let toward = if front { g } else { -g } * shading_eps(scene);
    let lit = |w: Vec3| {
        let o = at(w) + toward;
        !scene.occluded(Ray::new(light, o - light), 1.0 - DEPTH_EPS)
    };
    let mut parts = Vec::new();
    for corners in sub_triangles(if flat { 1 } else { k }) {
        lit_parts(corners, LIT_DEPTH, &lit, &mut parts);
    }
    for corners in parts {
        let sub = Triangle { v: corners.map(at) };
        let omega = solid_angle(light, &sub);
        if !(omega > 0.0) {
            continue;
        }
        let n = corners.map(|w| (normals[0] * w.x + normals[1] * w.y + normals[2] * w.z).normalize_or_zero());
        let incoming = sub.v.map(|v| (v - light).normalize_or_zero());
        // An area light's stratum emits less at a slant (none behind it).
        let falloff = incoming.map(|d| emitter.falloff(d));
        for (scatter, tint, sigma) in scatterings(&material) {
            let mut weight = 0.0;
            let mut dirs = [Vec3::ZERO; 3];
            for i in 0..3 {
                let (d, n) = (incoming[i], n[i]);
                let (w, s) = match scatter {
                    Scatter::Reflect => match material {
                        Material::Glass { ior } => (dielectric(d, n, ior, true).0, reflect(d, n)),
                        _ => (1.0, reflect(d, n)),
                    },
                    Scatter::Refract { ior } => match dielectric(d, n, ior, true) {
                        (fresnel, Some(t)) => (1.0 - fresnel, t),
                        (_, None) => (0.0, d),
                    },
                    Scatter::Transmit => (1.0, d),
                };
                weight += w * falloff[i] / 3.0;
                dirs[i] = s.try_normalize()?;
            }
            if weight > 0.0 {
                out.push(GlossyBeam {
                    beam: LightBeam { origins: sub.v, dirs, flux: omega },
                    power: intensity * tint * weight,
                    sigma,
                    light: index,
                    shadow: false,
                });
            }
        }
    }
    Some(out)
}
