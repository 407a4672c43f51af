//! Primary visibility of the renderer, a part of the image at a time: stratified primary rays for
//! a band of tile rows, or exact eye beams (001 §3) for a region, each followed by the shading of
//! what they see a tile at a time ([`Context::shade_tile`]).

use super::context::{Context, Lights, SHADE_SEED, Surface, Thread};
use super::shade_points::{Stretch, shade_points};
use super::shading::stratified;
use super::stats::Counters;
use crate::render::eye_budget::{grid_hits, trace_budget};
use crate::render::eye_regions::{EyeBeam, EyeStats, Fragment, Region, TILE, region_fragments};
use crate::render::primary_beam::nearest_first;
use beam_math::glam::Vec3;
use beam_scene::scene::{Camera, CameraFrame};
use rand::SeedableRng;
use rand_pcg::Pcg32;
use std::time::Instant;

/// What tracing one part of the image returns.
pub(super) struct Traced {
    /// The part.
    pub(super) region: Region,
    /// Its pixels, row-major.
    pub(super) pixels: Vec<Vec3>,
    pub(super) counters: Counters,
    /// The triangles its eye beams saw (empty with primary rays).
    pub(super) seen: Vec<bool>,
}

/// An eye-beam region before its shading: its [`Traced`] (pixels with the point lights' part),
/// its surface fragments sorted by tile, and how many fragments each tile has.
pub(super) struct EyeTraced {
    pub(super) traced: Traced,
    pub(super) surfaces: Vec<Surface>,
    pub(super) tiles: Vec<usize>,
    /// The lights the shading gathers: area lights only where eye beams lit the fragments of
    /// point lights, all where rays sampled the region.
    pub(super) lights: Lights,
}

/// Strata per pixel side where a region's eye beam would not pay, in the pixels that may hold an
/// edge: their quarters ([`Trace::adaptive_hits`]); one ray through the others' centres.
const RAY_GRID: u32 = 2;
const _: () = assert!(RAY_GRID == 2, "the strata are a pixel's quarters");

/// The rays a pixel of such a region counts as in the eye beam's budget ([`trace_budget`]). The
/// regions trace 1.1–3.4 a pixel (a centre, a ring of centres around the region, and one in each
/// quarter that borders an edge): 1.1–1.4 on the bunny, 1.5–2.7 on Sponza, Šibenik and the
/// conference room, 2.6–3.4 in the plant's and `foliage`'s leaves, at 128²–512². With 4 the conference
/// room at 256² kept eye beams that took 12% more than rays would (thread-seconds 0.150 against
/// 0.134); with 2, Šibenik at 256² sent 81% of its pixels to rays, and its RMSE against `--exact`
/// rose from 0.032 to 0.052.
const FALLBACK_RAYS: u32 = 3;

/// What the ray through a pixel's centre sees.
enum Centre {
    /// Nothing: the environment along this direction.
    Background(Vec3),
    /// One opaque surface, and the stretch of surface it lies on.
    Surface(Surface, Stretch),
    /// A `BLEND` surface and what lies behind it.
    Layered,
}

/// A shaded tile's radiance, as (index in its region's window, radiance) of its pixels.
pub(super) type TileRadiance = Vec<(usize, Vec3)>;

/// The tile (row, column) of the frame's grid a fragment lies in.
fn tile_of(s: &Surface) -> (u32, u32) {
    (s.y / TILE, s.x / TILE)
}

/// What every part shares.
pub(super) struct Trace<'a> {
    pub(super) ctx: &'a Context<'a>,
    pub(super) camera: &'a Camera,
    /// The seed of pixel `(x, y)`.
    pub(super) seed: &'a (dyn Fn(u32, u32) -> u64 + Sync),
    /// Triangles in the scene when eye beams record what they see, else 0.
    pub(super) n_prims: usize,
}

impl Trace<'_> {
    /// `options.primary_spp` stratified primary rays per pixel of `band`, shaded a tile at a time
    /// (`band.x0` on the frame's grid of tiles).
    pub(super) fn ray_band(&self, band: Region) -> Traced {
        let ctx = self.ctx;
        let mut t = Thread::default();
        let mut pixels = vec![Vec3::ZERO; band.len()];
        let k = ((ctx.options.primary_spp.max(1) as f32).sqrt() as u32).max(1);
        let (mut surfaces, mut points) = (Vec::new(), Vec::new());
        for x0 in (band.x0..band.x1).step_by(TILE as usize) {
            let start = Instant::now();
            surfaces.clear();
            let tile = Region { x0, x1: (x0 + TILE).min(band.x1), ..band };
            self.primary_hits(tile, k, &mut [], &mut surfaces, (&mut pixels, band), &mut t);
            t.c.primary_seconds += start.elapsed().as_secs_f64();
            ctx.shade_tile(&surfaces, Lights::All, (x0, band.y0), (&mut pixels, band), &mut points, &mut t);
        }
        self.finish(band, pixels, t, Vec::new())
    }

    /// The exact visible surface of `region` by one eye beam, its fragments in `window` (whole
    /// tiles of the frame's grid, within `region`) and the pixels of `window` with what point lights
    /// give the lit fragments (hard-shadow beams from the visible pieces, 001 §4.2). The surface
    /// fragments come sorted by tile, for [`Trace::shade_eye_tile`]. Where the beam would not pay
    /// or passes its budget while traced ([`trace_budget`]), [`Trace::ray_region`] instead.
    pub(super) fn eye_region(&self, region: Region, window: Region) -> EyeTraced {
        let (ctx, camera) = (self.ctx, self.camera);
        if ctx.cut_outs.as_ref().is_some_and(|c| c.may_show(camera, region)) {
            // Its pieces would show a cut-out, which only rays see through (the cheaper test first).
            let mut rays = self.ray_region(window);
            rays.traced.counters.cut_out_regions += 1;
            return rays;
        }
        // Half of what a primary ray and `--spp` shadow rays a pixel cost there, and a few times what
        // the rays of [`Trace::ray_region`] cost; none with `--exact`. The grid of rays that
        // predicts the beam's cost also seeds it.
        let hits = grid_hits(ctx.scene, camera, region);
        let budget = if ctx.options.exact {
            Some(f64::INFINITY)
        } else {
            trace_budget(ctx.scene, camera, (region, &hits), (1 + ctx.options.spp, FALLBACK_RAYS))
        };
        let Some(budget) = budget else { return self.ray_region(window) };
        let mut t = Thread::default();
        let mut pixels = vec![Vec3::ZERO; window.len()];
        let mut coverage = vec![0.0f32; window.len()];
        let mut seen = vec![false; self.n_prims];
        let start = Instant::now();
        let mut surfaces = Vec::new();
        let mut eye = EyeStats::default();
        // Fragments lit by point lights alone: nothing to shade but their lit parts.
        let mut covered = 0u64;
        let mut lit = None;
        // Cut-outs cast no exact hard shadows: with them, point lights are shaded by rays too.
        let point_shadows = !ctx.scene.has_cut_outs();
        let lit_only = point_shadows && !ctx.gathers(Lights::AreaOnly) && ctx.caustics.is_none();
        let seeds = nearest_first(hits);
        let beam = EyeBeam { region, window, point_shadows, lit_only, budget, seeds: Some(&seeds) };
        let traced = region_fragments(ctx.scene, camera, beam, &mut eye, &mut seen, |x, y, cov, f| {
            let i = window.index(x, y);
            match f {
                Fragment::Background { d } => {
                    coverage[i] += cov;
                    pixels[i] += cov * ctx.scene.environment.radiance(d);
                }
                Fragment::Covered => {
                    coverage[i] += cov;
                    covered += 1;
                }
                Fragment::Surface { prim, q, d } => {
                    coverage[i] += cov;
                    surfaces.push(Surface { x, y, weight: cov, prim, q, d, seed: (self.seed)(x, y), lent: [0.0; 2] });
                }
                Fragment::Lit { light, prim, points } => {
                    let Some(&(_, q)) = points.first() else { return };
                    // The fragments of one lit piece come in a row: its triangle's side and albedo once.
                    if lit.as_ref().is_none_or(|&(p, l, _)| (p, l) != (prim, light)) {
                        lit = Some((prim, light, ctx.point_lit(prim, light, camera.position, q)));
                    }
                    if let Some((_, _, Some(lit))) = &lit {
                        pixels[i] += lit.radiance(points);
                    }
                }
            }
        });
        if !traced {
            // Past its budget: the work spent counts, the pixels come from rays.
            let spent = start.elapsed().as_secs_f64();
            let mut rays = self.ray_region(window);
            rays.traced.counters.primary_seconds += spent;
            rays.traced.counters.over_budget += 1;
            rays.traced.counters.primary += eye.primary;
            return rays;
        }
        t.c.fragments += surfaces.len() as u64 + covered;
        // Shaded tile by tile (the frame's grid), so that neighbouring points share their candidate
        // occluders.
        t.c.lent_fragments += shade_points(ctx.scene, camera.position, (&mut surfaces, window), !ctx.options.exact);
        t.c.primary += eye.primary;
        t.c.beams += eye.shadow;
        t.c.shadow_beams += eye.shadow_beams;
        t.c.shade_points += surfaces.len() as u64;
        t.c.primary_seconds += start.elapsed().as_secs_f64();
        t.c.coverage_error = coverage.iter().fold(0.0f64, |m, &v| m.max(f64::from((1.0 - v).abs())));
        let tiles = surfaces.chunk_by(|a, b| tile_of(a) == tile_of(b)).map(<[Surface]>::len).collect();
        let lights = if point_shadows { Lights::AreaOnly } else { Lights::All };
        EyeTraced { traced: self.finish(window, pixels, t, seen), surfaces, tiles, lights }
    }

    /// [`Trace::eye_region`] by primary rays where the eye beam would not pay ([`trace_budget`]):
    /// a ray through each pixel's centre of `window`, one more in each quarter an edge may cross
    /// ([`Trace::adaptive_hits`]), each pixel's hits on one smooth stretch of surface shaded once,
    /// point lights by shadow rays.
    fn ray_region(&self, window: Region) -> EyeTraced {
        let (ctx, camera) = (self.ctx, self.camera);
        let mut t = Thread::default();
        let start = Instant::now();
        let mut seen = vec![false; self.n_prims];
        let mut surfaces = Vec::new();
        let mut pixels = vec![Vec3::ZERO; window.len()];
        self.adaptive_hits(window, &mut seen, &mut surfaces, (&mut pixels, window), &mut t);
        t.c.fragments += surfaces.len() as u64;
        t.c.lent_fragments += shade_points(ctx.scene, camera.position, (&mut surfaces, window), !ctx.options.exact);
        t.c.shade_points += surfaces.len() as u64;
        t.c.ray_pixels += window.len() as u64;
        t.c.primary_seconds += start.elapsed().as_secs_f64();
        let tiles = surfaces.chunk_by(|a, b| tile_of(a) == tile_of(b)).map(<[Surface]>::len).collect();
        EyeTraced { traced: self.finish(window, pixels, t, seen), surfaces, tiles, lights: Lights::All }
    }

    /// Shade one tile's surface fragments (of an [`EyeTraced`]) with thread state `t`: their
    /// radiance, each weighted by its coverage, as `(pixel, radiance)` of the region's window.
    pub(super) fn shade_eye_tile(
        &self,
        window: Region,
        tile: &[Surface],
        lights: Lights,
        t: &mut Thread,
    ) -> TileRadiance {
        let Some(first) = tile.first() else { return Vec::new() };
        let (ty, tx) = tile_of(first);
        let part = Region { x0: tx * TILE, y0: ty * TILE, x1: (tx + 1) * TILE, y1: (ty + 1) * TILE };
        let mut pixels = vec![Vec3::ZERO; part.len()];
        let mut points = Vec::new();
        self.ctx.shade_tile(tile, lights, (part.x0, part.y0), (&mut pixels, part), &mut points, t);
        let mut out = Vec::new();
        for ((x, y), _) in tile.iter().flat_map(Surface::targets) {
            let i = part.index(x, y);
            if pixels[i] != Vec3::ZERO {
                out.push((window.index(x, y), core::mem::take(&mut pixels[i])));
            }
        }
        out
    }

    /// `k × k` stratified primary rays a pixel of `rect`: each hit into `out` as a surface point
    /// of weight `1 / k²`, its triangle marked in `seen` (where `seen` is not empty); each miss
    /// adds `1 / k²` of the environment's radiance along it to its pixel of `pixels`, the row-major
    /// pixels of `part`. A `BLEND` surface's point has its coverage's part of that weight, and
    /// what lies behind it the rest ([`Scene::blended_hits`](beam_scene::scene::Scene::blended_hits)).
    fn primary_hits(
        &self,
        rect: Region,
        k: u32,
        seen: &mut [bool],
        out: &mut Vec<Surface>,
        (pixels, part): (&mut [Vec3], Region),
        t: &mut Thread,
    ) {
        let frame = self.camera.frame();
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let pixel = &mut pixels[part.index(x, y)];
                self.pixel_hits((x, y), (k, None, &frame), (&mut *seen, &mut *out), pixel, t);
            }
        }
    }

    /// [`Trace::primary_hits`] of pixel `(x, y)`, whose radiance is `pixel`: in every stratum, or
    /// only in those `i` (column `i % k`, row `i / k`) whose bit is set in `only` (each stratum's
    /// jitter is drawn all the same, so its ray does not depend on which others are traced).
    fn pixel_hits(
        &self,
        (x, y): (u32, u32),
        (k, only, frame): (u32, Option<u32>, &CameraFrame),
        (seen, out): (&mut [bool], &mut Vec<Surface>),
        pixel: &mut Vec3,
        t: &mut Thread,
    ) {
        let weight = 1.0 / (k * k) as f32;
        let seed = (self.seed)(x, y);
        let mut rng = Pcg32::seed_from_u64(seed);
        for i in 0..k * k {
            let (jx, jy) = stratified(i, k, &mut rng);
            if only.is_some_and(|bits| bits >> i & 1 == 0) {
                continue;
            }
            let ray = self.camera.ray(frame, x as f32 + jx, y as f32 + jy);
            t.c.camera_rays += 1;
            let d = ray.direction.normalize();
            let beyond = self.ctx.scene.blended_hits(ray, f32::INFINITY, |hit, share| {
                if let Some(s) = seen.get_mut(hit.prim as usize) {
                    *s = true;
                }
                let seed = seed ^ SHADE_SEED;
                out.push(Surface {
                    x,
                    y,
                    weight: weight * share,
                    prim: hit.prim,
                    q: ray.at(hit.t),
                    d,
                    seed,
                    lent: [0.0; 2],
                });
            });
            if beyond > 0.0 {
                *pixel += weight * beyond * self.ctx.scene.environment.radiance(ray.direction);
            }
        }
    }

    /// One primary ray through the centre of each pixel of `rect` (as `--method ray` traces it),
    /// and where the pixel may hold an edge, a stratified ray in each quarter of it that borders a
    /// neighbour (left, right, above or below, in the image) whose centre does not see the same
    /// smooth stretch of surface ([`Stretch`]), or in all four behind a `BLEND` surface
    /// ([`Trace::pixel_hits`] with [`RAY_GRID`] 2); the other quarters take what the centre sees.
    /// Each pixel's rays are its own (seeded by the pixel), whichever part of the image traces it.
    fn adaptive_hits(
        &self,
        rect: Region,
        seen: &mut [bool],
        out: &mut Vec<Surface>,
        (pixels, part): (&mut [Vec3], Region),
        t: &mut Thread,
    ) {
        let (scene, camera) = (self.ctx.scene, self.camera);
        let frame = camera.frame();
        // The centres of `rect` and of a ring of pixels around it: each one surface, or none.
        let ring = Region {
            x0: rect.x0.saturating_sub(1),
            y0: rect.y0.saturating_sub(1),
            x1: (rect.x1 + 1).min(camera.width.max(rect.x1)),
            y1: (rect.y1 + 1).min(camera.height.max(rect.y1)),
        };
        let mut centres: Vec<Centre> = Vec::with_capacity(ring.len());
        for y in ring.y0..ring.y1 {
            for x in ring.x0..ring.x1 {
                let ray = camera.ray(&frame, x as f32 + 0.5, y as f32 + 0.5);
                t.c.camera_rays += 1;
                let (mut last, mut layers) = (None, 0);
                let beyond = scene.blended_hits(ray, f32::INFINITY, |hit, _| {
                    layers += 1;
                    last = Some(hit);
                });
                centres.push(match (last, layers, beyond) {
                    (None, _, _) => Centre::Background(ray.direction),
                    (Some(hit), 1, 0.0) => {
                        let (q, d, seed) = (ray.at(hit.t), ray.direction.normalize(), (self.seed)(x, y) ^ SHADE_SEED);
                        let s = Surface { x, y, weight: 1.0, prim: hit.prim, q, d, seed, lent: [0.0; 2] };
                        Centre::Surface(s, Stretch::of(scene, camera.position, &s))
                    }
                    _ => Centre::Layered,
                });
            }
        }
        let at = |x: u32, y: u32| &centres[ring.index(x, y)];
        let one = |a: &Centre, b: &Centre| match (a, b) {
            (Centre::Background(_), Centre::Background(_)) => true,
            (Centre::Surface(_, a), Centre::Surface(_, b)) => a.joins(b),
            _ => false,
        };
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let c = at(x, y);
                let neighbours = [
                    (x > ring.x0).then(|| (x - 1, y)),
                    (x + 1 < ring.x1).then_some((x + 1, y)),
                    (y > ring.y0).then(|| (x, y - 1)),
                    (y + 1 < ring.y1).then_some((x, y + 1)),
                ];
                let pixel = &mut pixels[part.index(x, y)];
                // Whether each neighbour's centre sees another stretch: left, right, above, below.
                let differ = neighbours.map(|n| n.is_some_and(|(u, v)| !one(c, at(u, v))));
                // The quarters (the 2 × 2 strata) that border such a neighbour get a ray each, all
                // four behind a `BLEND` centre; the others take what the centre sees.
                let quarters: u32 = match c {
                    Centre::Layered => 0b1111,
                    _ => (0..4).filter(|&i| differ[i % 2] || differ[2 + i / 2]).map(|i| 1 << i).sum(),
                };
                if quarters != 0 {
                    self.pixel_hits((x, y), (RAY_GRID, Some(quarters), &frame), (&mut *seen, &mut *out), pixel, t);
                }
                let share = (4 - quarters.count_ones()) as f32 / 4.0;
                match c {
                    Centre::Surface(s, _) if share > 0.0 => {
                        if let Some(seen) = seen.get_mut(s.prim as usize) {
                            *seen = true;
                        }
                        out.push(Surface { weight: share, ..*s });
                    }
                    Centre::Background(direction) => *pixel += share * scene.environment.radiance(*direction),
                    _ => {}
                }
            }
        }
    }

    fn finish(&self, region: Region, pixels: Vec<Vec3>, t: Thread, seen: Vec<bool>) -> Traced {
        Traced { region, pixels, counters: t.c, seen }
    }
}
