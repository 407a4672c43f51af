//! The light stage's work for a slice of shade points, planned on the host: per point and light
//! (in the lights' order, as [`Context::direct`] sums them), a point light's shadow ray, an area
//! light's shadow-beam query (`beam`, unless a cut-out may hide part of the light) or stratified
//! shadow rays (`ray`), then the environment's
//! cosine-weighted rays where it is not shaded as lights. The samples are drawn from the same
//! random stream as the CPU renderer's: a camera sample's shade points in its depth-first order,
//! from the seed of its pixel.

use super::paths::ShadePoint;
use crate::render::lambert::clip_above;
use crate::render::renderer::context::{Context, SHADE_SEED, pixel_seed};
use crate::render::renderer::light_samples::{
    cosine_direction, light_integrand, light_sample, point_light, sample_light, tangents,
};
use beam_math::glam::Vec3;
use beam_math::{Aabb, Ray};
use beam_render::options::{Method, Shading};
use beam_render::queries::{LightPolygon, LightQuery};
use beam_render::tolerance::DEPTH_EPS;
use beam_scene::region::PixelRect;
use beam_scene::scene::Light;
use rand::SeedableRng;
use rand_pcg::Pcg32;
use rayon::prelude::*;

/// One light's share of a shade point's irradiance, to be read off the backend's answers.
#[derive(Clone, Copy, Debug)]
pub(super) enum Part {
    /// A point light: `irradiance` unless shadow ray `segment` is blocked.
    Point { segment: u32, irradiance: Vec3 },
    /// Area light `light` (an index into the context's lights) by shadow-beam query `query`.
    Beam { light: u32, query: u32 },
    /// Area light `light` by the shadow rays `segments` (those of its `spp` samples whose
    /// integrand does not vanish, with exact shading; all of them with fractions).
    Rays { light: u32, segments: (u32, u32), spp: u32 },
    /// The environment by its `spp` cosine-weighted rays `segments` (to infinity).
    Sky { segments: (u32, u32), spp: u32 },
}

/// The work of a slice of shade points.
#[derive(Default)]
pub(super) struct Plan {
    /// The points' parts, point by point.
    pub(super) parts: Vec<Part>,
    /// Where each point's parts end in `parts`.
    pub(super) ends: Vec<u32>,
    /// Shadow-ray segments `(ray, t_max)`.
    pub(super) segments: Vec<(Ray, f32)>,
    /// The irradiance integrand of each segment to an area light's sample (0 for the others).
    pub(super) integrands: Vec<f32>,
    /// Shadow-beam queries; a query's `light` indexes the table's polygons, then `polygons`.
    pub(super) queries: Vec<LightQuery>,
    /// Lights clipped to the plane of a surface under a normal texture, one a query
    /// ([`ShadePoint::surface`]): what their queries see.
    pub(super) polygons: Vec<LightPolygon>,
    /// Shadow rays among the segments (the others sample the environment).
    pub(super) shadow_rays: u64,
    /// Area lights of the `beam` method sampled by shadow rays because a cut-out may hide part of
    /// them.
    pub(super) cut_out_beams: u64,
}

/// The context's area lights as the backend takes them, and where each light is among them.
pub(super) struct LightTable {
    /// The area lights' polygons.
    pub(super) polygons: Vec<LightPolygon>,
    /// Index in `polygons` of each of the context's lights (`None`: a point light).
    slots: Vec<Option<u32>>,
}

impl LightTable {
    /// The table of `ctx`'s lights.
    pub(super) fn new(ctx: &Context<'_>) -> Self {
        let mut polygons = Vec::new();
        let slots = ctx
            .emitters
            .iter()
            .map(|e| {
                let polygon = LightPolygon::new(e.polygon(), e.normal)?;
                polygons.push(polygon);
                Some(polygons.len() as u32 - 1)
            })
            .collect();
        Self { polygons, slots }
    }
}

/// Most segments and queries one shade point may need under `ctx` (a bound to size slices by).
pub(super) fn most_work(ctx: &Context<'_>) -> usize {
    let spp = ctx.options.spp.max(1) as usize;
    let area = if ctx.options.method == Method::Beam { 1 } else { spp };
    let lights: usize = ctx.lights.iter().map(|l| if matches!(l, Light::Point { .. }) { 1 } else { area }).sum();
    lights + if sky_by_rays(ctx) { spp } else { 0 }
}

/// Whether the environment lights shade points by rays ([`Context::direct`]): where it is not
/// black and not shaded as lights.
fn sky_by_rays(ctx: &Context<'_>) -> bool {
    ctx.lights.len() == ctx.scene.lights.len() && !ctx.scene.environment.is_black()
}

/// The plan of `points` (whole camera samples of `band`, `per_pixel` samples a pixel).
pub(super) fn plan(
    ctx: &Context<'_>,
    table: &LightTable,
    points: &[ShadePoint],
    band: PixelRect,
    per_pixel: u32,
) -> Plan {
    let groups: Vec<&[ShadePoint]> = points.chunk_by(|a, b| a.sample == b.sample).collect();
    let plans: Vec<Plan> = groups
        .par_iter()
        .map(|group| {
            let pixel = group[0].sample / per_pixel;
            let (x, y) = (band.x0 + pixel % band.width(), band.y0 + pixel / band.width());
            let mut rng = Pcg32::seed_from_u64(pixel_seed(ctx.options.seed, x, y) ^ SHADE_SEED);
            let mut plan = Plan::default();
            for s in *group {
                plan_point(ctx, table, s, &mut rng, &mut plan);
                plan.ends.push(plan.parts.len() as u32);
            }
            plan
        })
        .collect();
    let mut all = Plan::default();
    for p in plans {
        all.append(p, table.polygons.len() as u32);
    }
    all
}

/// Add the parts of shade point `s` to `plan`, its samples drawn from `rng`.
fn plan_point(ctx: &Context<'_>, table: &LightTable, s: &ShadePoint, rng: &mut Pcg32, plan: &mut Plan) {
    let (p, n) = (s.p, s.n);
    // Under a normal texture, what lies below the surface's own plane it hides.
    let below = |to: Vec3| s.surface.is_some_and(|surface| surface.dot(to) <= 0.0);
    for (index, light) in ctx.lights.iter().enumerate() {
        if let Light::Point { position, intensity } = *light {
            if let Some((ray, irradiance)) = point_light(p, n, position, intensity).filter(|_| !below(position - p)) {
                let segment = plan.segment(ray, 1.0 - DEPTH_EPS, 0.0);
                plan.shadow_rays += 1;
                plan.parts.push(Part::Point { segment, irradiance });
            }
            continue;
        }
        let exact = ctx.shading(index) == Shading::Exact;
        // Quad and triangle lights always have a polygon.
        let Some(slot) = table.slots[index] else { continue };
        if !ctx.emitters[index].may_light(p, n, exact) {
            continue;
        }
        let emitter = &ctx.emitters[index];
        // A texture's alpha cuts the light where no beam can: rays see through the cut-outs
        // (`Context::light_beam` does the same, per cluster of points).
        let cut =
            || ctx.cut_outs.as_ref().is_some_and(|c| c.may_hide(&Aabb::new(p, p), emitter.polygon(), emitter.normal));
        match ctx.options.method {
            Method::Beam if !cut() => {
                let light = match s.surface {
                    Some(surface) => match beneath((emitter.polygon(), emitter.normal), p, surface) {
                        Beneath::No => slot,
                        Beneath::Wholly => continue,
                        Beneath::Partly(above) => {
                            plan.polygons.push(above);
                            (table.polygons.len() + plan.polygons.len() - 1) as u32
                        }
                    },
                    None => slot,
                };
                let query = plan.queries.len() as u32;
                plan.queries.push(LightQuery { p, n, light, clip_above: exact });
                plan.parts.push(Part::Beam { light: index as u32, query });
            }
            method => {
                plan.cut_out_beams += u64::from(method == Method::Beam);
                // As `Context::ray_irradiance`.
                let (ln, spp) = (emitter.normal, ctx.samples(p, n, index));
                let first = plan.segments.len() as u32;
                for i in 0..spp {
                    let (u, v) = light_sample(i, spp, rng);
                    let to = sample_light(light, u, v) - p;
                    let f = light_integrand(n, ln, to);
                    if exact && !(f > 0.0) || below(to) {
                        continue;
                    }
                    plan.segment(Ray::new(p, to), 1.0 - DEPTH_EPS, f);
                    plan.shadow_rays += 1;
                }
                let segments = (first, plan.segments.len() as u32);
                plan.parts.push(Part::Rays { light: index as u32, segments, spp });
            }
        }
    }
    if sky_by_rays(ctx) {
        // As `Context::environment_irradiance`.
        let spp = ctx.options.spp.max(1);
        let (u, v) = tangents(n);
        let first = plan.segments.len() as u32;
        for i in 0..spp {
            let w = cosine_direction((u, v, n), light_sample(i, spp, rng));
            if !below(w) {
                plan.segment(Ray::new(p, w), f32::INFINITY, 0.0);
            }
        }
        plan.parts.push(Part::Sky { segments: (first, plan.segments.len() as u32), spp });
    }
}

impl Plan {
    /// Add segment `(ray, t_max)` of integrand `f`; its index.
    fn segment(&mut self, ray: Ray, t_max: f32, f: f32) -> u32 {
        self.segments.push((ray, t_max));
        self.integrands.push(f);
        self.segments.len() as u32 - 1
    }

    /// Append `o`'s points, its indices moved past this plan's (its own polygons, from `table` on
    /// among the queries' lights, too).
    fn append(&mut self, o: Plan, table: u32) {
        let (segments, queries, parts) =
            (self.segments.len() as u32, self.queries.len() as u32, self.parts.len() as u32);
        let polygons = self.polygons.len() as u32;
        let range = |(a, b): (u32, u32)| (a + segments, b + segments);
        self.parts.extend(o.parts.into_iter().map(|part| match part {
            Part::Point { segment, irradiance } => Part::Point { segment: segment + segments, irradiance },
            Part::Beam { light, query } => Part::Beam { light, query: query + queries },
            Part::Rays { light, segments, spp } => Part::Rays { light, segments: range(segments), spp },
            Part::Sky { segments, spp } => Part::Sky { segments: range(segments), spp },
        }));
        self.ends.extend(o.ends.into_iter().map(|e| e + parts));
        self.segments.extend(o.segments);
        self.integrands.extend(o.integrands);
        self.queries.extend(
            o.queries
                .into_iter()
                .map(|q| LightQuery { light: if q.light >= table { q.light + polygons } else { q.light }, ..q }),
        );
        self.polygons.extend(o.polygons);
        self.shadow_rays += o.shadow_rays;
        self.cut_out_beams += o.cut_out_beams;
    }
}

/// Where a light lies against the plane of a surface under a normal texture.
enum Beneath {
    /// Wholly above it.
    No,
    /// Wholly on or below it: hidden.
    Wholly,
    /// Across it: the part above.
    Partly(LightPolygon),
}

/// Where light `polygon` (its lit side's unit normal `normal`, at most 4 corners) lies against the
/// plane through `p` of unit normal `surface`, as `Context::beam_irradiance` clips it.
fn beneath((polygon, normal): (&[Vec3], Vec3), p: Vec3, surface: Vec3) -> Beneath {
    if polygon.iter().all(|&c| surface.dot(c - p) >= 0.0) {
        return Beneath::No;
    }
    // At most 5 corners: within the backend's polygons.
    let above = clip_above(polygon, p, surface);
    match LightPolygon::new(&above, normal) {
        Some(part) => Beneath::Partly(part),
        None => Beneath::Wholly,
    }
}
