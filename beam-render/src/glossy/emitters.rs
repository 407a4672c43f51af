//! The point sources the light volumes are traced from. 002 traces its beams from point lights;
//! an area light (quad or triangle) of radiance `L` and area `A` is taken as `k × k` stratified
//! point emitters, one at the centre of each equal-area stratum, each of radiant intensity
//! `L·A/k²·cosθ` at angle θ from the light's normal (none behind it): what the stratum emits, as
//! seen from afar. `k` is [`AREA_STRATA`] unless the scene has more lights than the GPU's shadow
//! mask holds ([`MAX_EMITTERS`]), then smaller. Beams, shadow beams and the renderer's direct light
//! all use these emitters, so an area light's shadows and caustics are `k²` overlaid point-light
//! ones (banded where a point source's would be sharp); the photon reference
//! (beam-cpu's `glossy_photons`) and its direct light (`reference_direct`) sample the whole area
//! instead, the ground truth those bands converge to as `k` grows.

use crate::tolerance::shading_eps;
use beam_math::glam::Vec3;
use beam_scene::scene::{Light, Scene};

/// Most emitters the light volumes trace from: the width of the GPU gather's shadow mask.
pub const MAX_EMITTERS: usize = 32;

/// Strata per side of an area light (so `AREA_STRATA²` emitters each), when the scene's light
/// count allows.
pub const AREA_STRATA: u32 = 4;

/// Shadow rays per area light and receiver point of `beam_cpu::glossy::reference_direct` (16 × 16 strata, jittered).
pub const REFERENCE_AREA_RAYS: u32 = 256;

/// A point source of light volumes: a point light, or one stratum of an area light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emitter {
    /// Where it emits from (an area light's stratum centre, moved off the emitting surface by the
    /// scene's shading offset along its normal, so that rays from it do not hit its own triangles).
    pub position: Vec3,
    /// Radiant intensity (W/sr per channel): in every direction for a point light, along
    /// `normal` for an area light's stratum.
    pub intensity: Vec3,
    /// Unit normal of an area light's emitting side; zero for a point light (isotropic).
    pub normal: Vec3,
    /// Index of its light in the scene's lights.
    pub light: u32,
}

impl Emitter {
    /// True for a point light (isotropic), false for a stratum of an area light.
    #[must_use]
    pub fn is_point(&self) -> bool {
        self.normal == Vec3::ZERO
    }

    /// Fraction of [`Self::intensity`] emitted towards unit direction `d` (leaving the emitter):
    /// 1 for a point light, `max(0, n·d)` for an area light's stratum (Lambertian emission).
    #[must_use]
    pub fn falloff(&self, d: Vec3) -> f32 {
        if self.is_point() { 1.0 } else { self.normal.dot(d).max(0.0) }
    }

    /// Radiant intensity towards unit direction `d`.
    #[must_use]
    pub fn towards(&self, d: Vec3) -> Vec3 {
        self.intensity * self.falloff(d)
    }
}

/// True when `light` emits: a point light, or an area light of positive, finite area and normal.
fn emits(light: &Light) -> bool {
    match light {
        Light::Point { position, intensity } => position.is_finite() && intensity.is_finite(),
        _ => light.area() > 0.0 && light.area().is_finite() && light.normal() != Vec3::ZERO,
    }
}

/// Strata per side of each area light of `scene`: [`AREA_STRATA`], fewer when the point lights
/// plus `k²` per area light would pass [`MAX_EMITTERS`] (at least 1).
#[must_use]
pub fn area_strata(scene: &Scene) -> u32 {
    let lights = scene.lights.iter().filter(|l| emits(l));
    let (points, areas) = lights.fold((0usize, 0usize), |(p, a), l| match l {
        Light::Point { .. } => (p + 1, a),
        _ => (p, a + 1),
    });
    let room = MAX_EMITTERS.saturating_sub(points) / areas.max(1);
    (1..=AREA_STRATA).rev().find(|k| (k * k) as usize <= room).unwrap_or(1)
}

/// The point `(s, t) ∈ [0, 1]²` of area light `light`, uniform in area: `corner + s·u + t·v` for a
/// quad, the square folded onto the triangle for a triangle; a point light's position.
#[must_use]
pub fn area_point(light: &Light, s: f32, t: f32) -> Vec3 {
    match *light {
        Light::Point { position, .. } => position,
        Light::Quad { corner, edge_u, edge_v, .. } => corner + edge_u * s + edge_v * t,
        Light::Triangle { v, .. } => {
            let (s, t) = if s + t > 1.0 { (1.0 - s, 1.0 - t) } else { (s, t) };
            v[0] + (v[1] - v[0]) * s + (v[2] - v[0]) * t
        }
    }
}

/// The whole of `light` as one emitter at its centre (all its area's intensity, `L·A` along its
/// normal); `None` when it does not emit (zero area, non-finite).
#[must_use]
pub fn whole(scene: &Scene, light: &Light, index: u32) -> Option<Emitter> {
    if !emits(light) {
        return None;
    }
    let normal = light.normal();
    let intensity = match light {
        Light::Point { .. } => light.power(),
        _ => light.power() * light.area(),
    };
    Some(Emitter { position: light.center() + normal * shading_eps(scene), intensity, normal, light: index })
}

/// The emitters of `scene`, light by light: each point light, and [`area_strata`]² per area light
/// (stratum centres; a triangle's strata are the sub-triangles of a `k × k` barycentric grid).
#[must_use]
pub fn emitters(scene: &Scene) -> Vec<Emitter> {
    stratified(scene, area_strata(scene))
}

/// The emitters of `scene` with `k × k` strata per area light (as [`emitters`]; `k` at least 1).
#[must_use]
pub fn stratified(scene: &Scene, k: u32) -> Vec<Emitter> {
    let k = k.max(1);
    let eps = shading_eps(scene);
    let mut out = Vec::new();
    for (i, light) in scene.lights.iter().enumerate() {
        let Some(e) = whole(scene, light, i as u32) else { continue };
        if matches!(light, Light::Point { .. }) {
            out.push(e);
            continue;
        }
        let share = Emitter { intensity: e.intensity / (k * k) as f32, ..e };
        let at = |p: Vec3| Emitter { position: p + e.normal * eps, ..share };
        match *light {
            Light::Triangle { v, .. } => out.extend(sub_triangles(k).map(|w| {
                let c = (w[0] + w[1] + w[2]) / 3.0;
                at(v[0] * c.x + v[1] * c.y + v[2] * c.z)
            })),
            _ => {
                let centre = |i: u32| (i as f32 + 0.5) / k as f32;
                out.extend((0..k * k).map(|i| at(area_point(light, centre(i % k), centre(i / k)))));
            }
        }
    }
    out
}

/// The sub-triangles of a `k × k` barycentric grid over a triangle, as barycentric corners (the
/// winding of the triangle's own).
pub(super) fn sub_triangles(k: u32) -> impl Iterator<Item = [Vec3; 3]> {
    let w = move |i: u32, j: u32| Vec3::new(1.0 - (i + j) as f32 / k as f32, i as f32 / k as f32, j as f32 / k as f32);
    (0..k).flat_map(move |i| {
        (0..k - i).flat_map(move |j| {
            let up = [w(i, j), w(i + 1, j), w(i, j + 1)];
            let down = (i + j + 1 < k).then(|| [w(i + 1, j), w(i + 1, j + 1), w(i, j + 1)]);
            std::iter::once(up).chain(down)
        })
    })
}
