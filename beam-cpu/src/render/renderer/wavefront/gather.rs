//! The light stage's answers: a slice's shadow rays and shadow beams sent to the backend in
//! batches, the beams it gave up on traced on the host ([`light_seen`]), and each shade point's
//! irradiance summed from its parts in the order [`Context::direct`] sums them.

use super::batches::{any_hits, light_visibility};
use super::exact_beam::light_seen;
use super::paths::ShadePoint;
use super::plan::{LightTable, Part, Plan};
use crate::render::renderer::context::Context;
use crate::render::renderer::stats::Counters;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::options::Shading;
use beam_render::queries::{BeamQueries, LightPolygon, LightSeen};
use rayon::prelude::*;
use std::borrow::Cow;
use std::f32::consts::PI;
use std::time::Instant;

/// A shade point's radiance towards its pixel, weighted, and whether it sampled the environment.
pub(super) struct Lit {
    /// `weight × albedo / π × E`.
    pub(super) radiance: Vec3,
    /// Whether part of `E` came from the environment's rays (the pixel is not exact).
    pub(super) sampled: bool,
}

/// The radiance of each of `points` by `plan`, its visibility from `backend`; the work counted
/// into `c`.
pub(super) fn gather(
    ctx: &Context<'_>,
    backend: &dyn BeamQueries,
    table: &LightTable,
    points: &[ShadePoint],
    plan: &Plan,
    c: &mut Counters,
) -> Result<Vec<Lit>, BackendError> {
    let scene = ctx.scene;
    let start = Instant::now();
    let hidden = any_hits(backend, scene, &plan.segments)?;
    // The lights, then those clipped to a surface under a normal texture.
    let polygons: Cow<'_, [LightPolygon]> = if plan.polygons.is_empty() {
        Cow::Borrowed(&table.polygons)
    } else {
        Cow::Owned([table.polygons.as_slice(), &plan.polygons].concat())
    };
    let answers = light_visibility(backend, scene, &polygons, &plan.queries)?;
    // The beams the backend gave up on, traced here.
    let overflow: Vec<usize> = answers.iter().enumerate().filter(|(_, a)| a.is_none()).map(|(i, _)| i).collect();
    let traced: Vec<LightSeen> = overflow
        .par_iter()
        .map(|&i| light_seen(&scene.bvh, &scene.triangles, &polygons[plan.queries[i].light as usize], &plan.queries[i]))
        .collect();
    let mut seen: Vec<LightSeen> = answers.into_iter().map(Option::unwrap_or_default).collect();
    for (&i, t) in overflow.iter().zip(traced) {
        seen[i] = t;
    }
    c.shadow_seconds += start.elapsed().as_secs_f64();
    c.shadow_rays += plan.shadow_rays;
    c.shadow_beams += plan.cut_out_beams;
    c.cut_out_beams += plan.cut_out_beams;
    c.environment_rays += plan.segments.len() as u64 - plan.shadow_rays;
    c.shadow_beams += plan.queries.len() as u64;
    c.overflow_beams += overflow.len() as u64;
    c.shade_points += points.len() as u64;
    let start = Instant::now();
    let lit = points
        .par_iter()
        .enumerate()
        .map(|(i, s)| {
            let begin = if i == 0 { 0 } else { plan.ends[i - 1] as usize };
            let parts = &plan.parts[begin..plan.ends[i] as usize];
            let (e, sampled) = irradiance(ctx, s, parts, plan, (&hidden, &seen));
            Lit { radiance: s.weight * (s.albedo / PI * e), sampled }
        })
        .collect();
    c.shading_seconds += start.elapsed().as_secs_f64();
    Ok(lit)
}

/// The irradiance at shade point `s` from its `parts` of `plan`, given which segments are
/// `hidden` and what each query `seen`; and whether the environment's rays gave part of it.
fn irradiance(
    ctx: &Context<'_>,
    s: &ShadePoint,
    parts: &[Part],
    plan: &Plan,
    (hidden, seen): (&[bool], &[LightSeen]),
) -> (Vec3, bool) {
    let (p, n) = (s.p, s.n);
    let mut e = Vec3::ZERO;
    let mut sampled = false;
    for &part in parts {
        match part {
            Part::Point { segment, irradiance } => {
                if !hidden[segment as usize] {
                    e += irradiance;
                }
            }
            Part::Beam { light, query } => {
                let (index, seen) = (light as usize, seen[query as usize]);
                let value = match ctx.shading(index) {
                    Shading::Exact => seen.irradiance.max(0.0),
                    Shading::Fraction => ctx.fraction_irradiance(p, n, index, seen.fraction),
                };
                e += ctx.lights[index].power() * value;
            }
            Part::Rays { light, segments: (a, b), spp } => {
                let (mut visible, mut integral) = (0u32, 0.0f32);
                for k in (a as usize..b as usize).filter(|&k| !hidden[k]) {
                    visible += 1;
                    integral += plan.integrands[k];
                }
                let index = light as usize;
                e += ctx.lights[index].power() * ctx.ray_estimate(p, n, index, spp, (visible, integral));
            }
            Part::Sky { segments: (a, b), spp } => {
                let environment = &ctx.scene.environment;
                let mut sum = Vec3::ZERO;
                for k in (a as usize..b as usize).filter(|&k| !hidden[k]) {
                    sum += environment.radiance(plan.segments[k].0.direction);
                }
                e += PI * sum / spp as f32;
                sampled = true;
            }
        }
    }
    (e, sampled)
}
