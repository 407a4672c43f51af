//! The shading every renderer shares (001 eq. 1 and 2): per shade point, direct light whose
//! visibility comes from exact shadow beams (001 §5) or stratified shadow rays, the caustic
//! irradiance, and mirror and glass followed by Whitted rays; per tile, the shade points of a
//! region with their candidate occluders gathered first.

use super::context::{Context, Lights, Surface, Thread};
use super::emitters::Emitter;
use super::light_samples::{light_integrand, light_sample, point_light, sample_light};
use crate::render::eye_regions::{Region, TILE};
use crate::render::lambert::point_source_irradiance;
use crate::render::tile_shadows::BLOCKS;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::irradiance_map::IrradianceMap;
use beam_render::options::{Method, RenderOptions, Shading};
use beam_render::specular::{MAX_DEPTH, specular_rays};
use beam_render::tolerance::DEPTH_EPS;
use beam_scene::scene::{Light, Material, Scene};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use std::time::Instant;

impl Context<'_> {
    /// Radiance arriving along `ray` (after `depth` mirror and glass bounces): the surface it
    /// hits shaded, or the environment's radiance from its direction where it leaves the scene.
    pub(super) fn radiance(&self, ray: Ray, depth: u32, rng: &mut Pcg32, t: &mut Thread) -> Vec3 {
        t.c.camera_rays += 1;
        let Some(hit) = self.scene.closest_hit(ray, f32::INFINITY) else {
            return self.scene.environment.radiance(ray.direction);
        };
        self.shade(hit.prim, ray.at(hit.t), ray.direction.normalize(), depth, Lights::All, rng, t)
    }

    /// The point that gathers direct light for point `p` of `prim` seen along `d` (offset off the
    /// surface on the viewer's side) and its normal; `None` unless the material is diffuse or glossy.
    pub(super) fn gather_point(&self, prim: u32, p: Vec3, d: Vec3) -> Option<(Vec3, Vec3)> {
        if !matches!(self.scene.material(prim), Material::Diffuse { .. } | Material::Glossy { .. }) {
            return None;
        }
        let n = self.scene.normal(prim);
        let n = if n.dot(d) < 0.0 { n } else { -n };
        Some((p + n * self.eps, n))
    }

    /// Radiance leaving point `p` of triangle `prim` towards `−d`, with the direct light of `lights`
    /// (at the first surface; every light after a mirror or glass bounce).
    pub(super) fn shade(
        &self,
        prim: u32,
        p: Vec3,
        d: Vec3,
        depth: u32,
        lights: Lights,
        rng: &mut Pcg32,
        t: &mut Thread,
    ) -> Vec3 {
        let mut n = self.scene.normal(prim);
        let entering = n.dot(d) < 0.0;
        if !entering {
            n = -n;
        }
        match self.scene.material(prim) {
            Material::Emissive { .. } => self.scene.emission_at(prim, p),
            Material::Diffuse { .. } | Material::Glossy { .. } => {
                let albedo = self.scene.albedo_at(prim, p);
                // Lit by its normal texture's normal, over the part of each light above the
                // surface itself too ([`Thread::surface`]).
                let shading_normal = self.scene.mapped_normal(prim, p, n);
                t.surface = (shading_normal != n).then_some(n);
                let mut e = self.direct(p + n * self.eps, shading_normal, lights, depth == 0, rng, t);
                t.surface = None;
                if let Some(map) = self.caustics {
                    e += map.irradiance(prim, p, d);
                }
                // Sampled parts of lights leave the radiance within this much of the exact one.
                let bound = core::mem::take(&mut t.c.pending_bound);
                if bound > 0.0 {
                    t.c.max_error_bound = t.c.max_error_bound.max(albedo.max_element() / std::f32::consts::PI * bound);
                }
                albedo / std::f32::consts::PI * e
            }
            Material::Mirror { .. } | Material::Glass { .. } | Material::ThinGlass { .. } if depth < MAX_DEPTH => {
                specular_rays(self.scene, self.eps, prim, p, d)
                    .into_iter()
                    .flatten()
                    .flatten()
                    .map(|(ray, weight)| weight * self.radiance(ray, depth + 1, rng, t))
                    .sum()
            }
            Material::Mirror { .. } | Material::Glass { .. } | Material::ThinGlass { .. } => Vec3::ZERO,
        }
    }

    /// Irradiance at `p` (normal `n`) from `lights` (at a tile's first surfaces, `first`, only
    /// those that face the tile; with beams, a constant environment's faces among them) and from
    /// an environment not shaded as lights ([`Context::environment_irradiance`]: a map, or a
    /// constant sky with rays).
    pub(super) fn direct(
        &self,
        p: Vec3,
        n: Vec3,
        lights: Lights,
        first: bool,
        rng: &mut Pcg32,
        t: &mut Thread,
    ) -> Vec3 {
        if !self.gathers(lights) {
            return Vec3::ZERO;
        }
        let start = (self.options.method == Method::Beam).then(Instant::now);
        let facing = if first { t.facing.take() } else { None };
        // The sky's faces as lights, unless a cut-out may hide one ([`Context::sky_behind_cut_outs`]).
        let sky_sampled = self.sky_behind_cut_outs(p, n, t);
        let end = if sky_sampled { self.scene.lights.len() } else { self.lights.len() };
        let mut e = Vec3::ZERO;
        match &facing {
            Some(list) => {
                for &index in list.iter().filter(|&&i| (i as usize) < end) {
                    e += self.light(p, n, index as usize, lights, rng, t);
                }
            }
            None => {
                for index in 0..end {
                    e += self.light(p, n, index, lights, rng, t);
                }
            }
        }
        if first {
            t.facing = facing;
        }
        if end == self.scene.lights.len() && !self.scene.environment.is_black() {
            e += self.environment_irradiance(p, n, rng, t);
        }
        if let Some(start) = start {
            t.c.shadow_seconds += start.elapsed().as_secs_f64();
        }
        e
    }

    /// Irradiance at `p` (normal `n`) from light `index`, if it is one of `lights`.
    fn light(&self, p: Vec3, n: Vec3, index: usize, lights: Lights, rng: &mut Pcg32, t: &mut Thread) -> Vec3 {
        match self.lights[index] {
            Light::Point { .. } if lights == Lights::AreaOnly => Vec3::ZERO,
            Light::Point { position, intensity } => {
                let above = t.surface.is_none_or(|s| s.dot(position - p) > 0.0);
                if let Some((ray, e)) = point_light(p, n, position, intensity).filter(|_| above) {
                    t.c.shadow_rays += 1;
                    if !self.occluded((ray.origin, ray.direction), 1.0 - DEPTH_EPS, &mut None) {
                        return e;
                    }
                }
                Vec3::ZERO
            }
            ref light => light.power() * self.area_light(p, n, index, rng, t),
        }
    }

    /// Irradiance per unit radiance from area light `index`.
    pub(super) fn area_light(&self, p: Vec3, n: Vec3, index: usize, rng: &mut Pcg32, t: &mut Thread) -> f32 {
        if !self.emitters[index].may_light(p, n, self.shading(index) == Shading::Exact) {
            return 0.0;
        }
        match self.options.method {
            Method::Beam => self.beam_irradiance(p, n, index, rng, t),
            Method::Ray => self.ray_irradiance(p, n, index, false, rng, t),
        }
    }

    /// Irradiance per unit radiance from area light `index` by `--spp` stratified shadow rays (a
    /// sky face its share, [`Context::samples`]; those whose integrand vanishes, behind the point
    /// or the light, are not traced; with `clear`, known to see the whole light, none is).
    pub(super) fn ray_irradiance(
        &self,
        p: Vec3,
        n: Vec3,
        index: usize,
        clear: bool,
        rng: &mut Pcg32,
        t: &mut Thread,
    ) -> f32 {
        let light = &self.lights[index];
        let ln = self.emitters[index].normal;
        let spp = self.samples(p, n, index);
        let (mut visible, mut integral) = (0u32, 0.0f32);
        let mut last = None;
        for i in 0..spp {
            let (s, r) = light_sample(i, spp, rng);
            let to = sample_light(light, s, r) - p;
            let f = light_integrand(n, ln, to);
            // Under a normal texture, what lies below the surface itself it hides.
            let below = t.surface.is_some_and(|s| s.dot(to) <= 0.0);
            if self.shading(index) == Shading::Exact && !(f > 0.0) || below {
                continue;
            }
            if clear || {
                t.c.shadow_rays += 1;
                !self.occluded((p, to), 1.0 - DEPTH_EPS, &mut last)
            } {
                visible += 1;
                integral += f;
            }
        }
        self.ray_estimate(p, n, index, spp, (visible, integral))
    }

    /// [`Context::ray_irradiance`]'s estimate from its `spp` samples of area light `index`, of which
    /// `visible` reached the light, their integrands ([`light_integrand`]) summing to `integral`.
    pub(super) fn ray_estimate(
        &self,
        p: Vec3,
        n: Vec3,
        index: usize,
        spp: u32,
        (visible, integral): (u32, f32),
    ) -> f32 {
        let Emitter { normal: ln, area, center, .. } = self.emitters[index];
        match self.shading(index) {
            Shading::Fraction => point_source_irradiance(p, n, center, ln, area, visible as f32 / spp as f32),
            Shading::Exact => area * integral / spp as f32,
        }
    }
}

impl Context<'_> {
    /// Shade the surface points of the tile whose corner is `(x0, y0)` into `pixels`, the
    /// row-major pixels of `part`, `weight ×` radiance each. With beams, the points' candidate
    /// occluders are gathered first, a block of the tile at a time
    /// ([`TileShadows`](crate::render::tile_shadows::TileShadows)).
    pub(super) fn shade_tile(
        &self,
        surfaces: &[Surface],
        lights: Lights,
        (x0, y0): (u32, u32),
        (pixels, part): (&mut [Vec3], Region),
        points: &mut Vec<(usize, Vec3)>,
        t: &mut Thread,
    ) {
        let start = Instant::now();
        let shadow_before = t.c.shadow_seconds;
        self.cull_lights(surfaces, t);
        t.partial.clear();
        if self.options.method == Method::Beam && self.gathers(lights) {
            let start = Instant::now();
            points.clear();
            points.extend(
                surfaces
                    .iter()
                    .filter_map(|s| Some((block_of(s.x - x0, s.y - y0), self.gather_point(s.prim, s.q, s.d)?.0))),
            );
            let scene_lights = self.scene.lights.len();
            if self.beams_pay() {
                t.tile.build(self.scene, (&self.lights, scene_lights), points, self.options.occluders);
                t.c.shafts += core::mem::take(&mut t.tile.shafts);
                t.c.shaft_bvh_steps += core::mem::take(&mut t.tile.bvh_steps);
            } else {
                // A constant environment's faces enclose the scene: their shafts would meet it all.
                let facing = t.facing.as_deref().unwrap_or_default();
                t.clear.build(self.scene, (&self.lights, scene_lights), facing, points, self.options.spp);
                t.c.shafts += core::mem::take(&mut t.clear.shafts);
                t.c.shaft_bvh_steps += core::mem::take(&mut t.clear.bvh_steps);
            }
            t.c.shadow_seconds += start.elapsed().as_secs_f64();
        }
        // Pixels of the tile with a shade point whose light was sampled in part.
        let mut inexact = [false; (TILE * TILE) as usize];
        for s in surfaces {
            t.block = block_of(s.x - x0, s.y - y0);
            let mut rng = Pcg32::seed_from_u64(s.seed);
            let (sampled, sky) = (t.c.sampled_beams, t.c.environment_rays);
            let l = self.shade(s.prim, s.q, s.d, 0, lights, &mut rng, t);
            let sampled = t.c.sampled_beams > sampled || t.c.environment_rays > sky;
            for ((x, y), weight) in s.targets() {
                pixels[part.index(x, y)] += weight * l;
                if sampled {
                    inexact[((y - y0) * TILE + x - x0) as usize] = true;
                }
            }
        }
        // Only the pixels asked for: a crop shades whole rows of tiles around itself.
        let crop = self.options.region();
        let asked = |i: usize| crop.contains(x0 + i as u32 % TILE, y0 + i as u32 / TILE);
        t.c.inexact_pixels += (0..inexact.len()).filter(|&i| inexact[i] && asked(i)).count() as u64;
        t.facing = None;
        t.c.shading_seconds += start.elapsed().as_secs_f64() - (t.c.shadow_seconds - shadow_before);
    }
}

impl Context<'_> {
    /// Keeps in `t.facing` the lights that face the box of the tile's `surfaces` (point lights
    /// all): the others cannot light any of its points.
    fn cull_lights(&self, surfaces: &[Surface], t: &mut Thread) {
        let (lo, hi) =
            surfaces.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), s| (lo.min(s.q), hi.max(s.q)));
        // The gather points sit `eps` off their surfaces.
        let (lo, hi) = (lo - Vec3::splat(self.eps), hi + Vec3::splat(self.eps));
        let mut list = t.facing.take().unwrap_or_default();
        list.clear();
        list.extend(
            self.emitters
                .iter()
                .enumerate()
                .filter(|(_, e)| e.polygon().is_empty() || e.faces_box(lo, hi))
                .map(|(i, _)| i as u32),
        );
        if !surfaces.is_empty() {
            t.c.culled_lights += (self.emitters.len() - list.len()) as u64;
        }
        t.facing = Some(list);
    }
}

/// The shading every renderer shares, for one shade point: the radiance leaving point `p` of
/// triangle `prim` towards `−d`, with direct light by `options.method`, the irradiance of
/// `caustics` on diffuse surfaces, and mirror and glass followed by rays. `seed` seeds the
/// shadow-ray samples.
#[must_use]
pub fn shade_point(
    scene: &Scene,
    options: &RenderOptions,
    caustics: Option<&IrradianceMap>,
    prim: u32,
    p: Vec3,
    d: Vec3,
    seed: u64,
) -> Vec3 {
    with_context(scene, options, caustics, |ctx| {
        ctx.shade(prim, p, d, 0, Lights::All, &mut Pcg32::seed_from_u64(seed), &mut Thread::default())
    })
}

/// Radiance arriving along `ray` (the scene's environment where it leaves the scene), shaded as
/// [`shade_point`].
#[must_use]
pub fn trace_radiance(
    scene: &Scene,
    options: &RenderOptions,
    caustics: Option<&IrradianceMap>,
    ray: Ray,
    seed: u64,
) -> Vec3 {
    with_context(scene, options, caustics, |ctx| {
        ctx.radiance(ray, 0, &mut Pcg32::seed_from_u64(seed), &mut Thread::default())
    })
}

/// Runs `f` with the shading context of `scene`, shadow rays traced by its own BVH.
fn with_context<R>(
    scene: &Scene,
    options: &RenderOptions,
    caustics: Option<&IrradianceMap>,
    f: impl FnOnce(&Context<'_>) -> R,
) -> R {
    f(&Context::new(scene, options, None, caustics))
}

/// Offset in the pixel of sample `i` of `k × k` stratified samples, jittered by `rng` (the pixel's
/// centre when `k == 1`).
pub fn stratified(i: u32, k: u32, rng: &mut impl Rng) -> (f32, f32) {
    if k == 1 {
        return (0.5, 0.5);
    }
    (((i % k) as f32 + rng.random::<f32>()) / k as f32, ((i / k) as f32 + rng.random::<f32>()) / k as f32)
}

/// The block (of [`BLOCKS`]² in a tile) of the pixel at `(x, y)` from the tile's corner.
pub(super) fn block_of(x: u32, y: u32) -> usize {
    let side = TILE as usize / BLOCKS;
    x as usize / side + y as usize / side * BLOCKS
}
