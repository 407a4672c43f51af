//! One shade point's shadow beam to one area light, from start to irradiance: the light clipped to
//! the tangent plane (only that part lights the point), its candidate occluders taken by splitting
//! or by their edges as the point's cluster decided, within a work budget; past the budget the part
//! of the light left unresolved is sampled by shadow rays with the ratio estimator (Heitz et al.
//! 2018), so that a part the samples see wholly lit or wholly hidden comes out exact, and the
//! interval `[0, unoccluded irradiance of that part]` is the error's bound.

use super::context::{Context, Thread};
use super::light_samples::sample_light;
use super::rounds::draw_light;
use super::stats::Counters;
use crate::render::clear_shafts::LAMBERT_RAYS;
use crate::render::lambert::{clip_above, point_source_irradiance, polygon_irradiance};
use crate::render::shadow_beam::ShadowBeam;
use crate::render::shadow_beam::visible::light_beam;
use crate::render::shadow_beam::walk::trace_bvh;
use crate::render::silhouettes::WindingWork;
use crate::render::tile_shadows::Mode;
use beam_math::Aabb;
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, Quad, WindingError};
use beam_render::options::Shading;
use beam_render::tolerance::DEPTH_EPS;
use rand_pcg::Pcg32;

/// A shadow beam's budget per shadow ray of `--spp`, in piece splits (a candidate's test counts
/// 1/32 of one): by this machine's timings a split costs about as much as a shadow ray (170 and
/// 200 ns), so a beam may spend about twice the ray render's time on its point before it samples.
/// Rays stopped by their point's last occluder cost less (140 ns a ray under a light over all of
/// Sponza), but budgets of 1 and 1.5 splits a ray changed the suite's Sponza rows by 1–3%, inside
/// the runs' spread.
const SPLITS_PER_RAY: u64 = 2;

/// Fewest rays of `--spp` for which shadow beams are traced at all: below it every light is
/// sampled as the ray method samples it, since a beam's own work (its share of its cluster's shaft
/// and edges, its set-up) costs a point about as much as this many rays (2–3 µs against 0.18 µs a
/// ray on this machine; 36 small emitters at 7 rays each: 8 µs a beam).
pub(super) const MIN_BEAM_SPP: u32 = 16;

impl Context<'_> {
    /// Whether shadow beams are traced at all ([`MIN_BEAM_SPP`]).
    pub(super) fn beams_pay(&self) -> bool {
        self.options.exact || self.options.spp >= MIN_BEAM_SPP
    }

    /// Irradiance per unit radiance at `p` (normal `n`) from area light `index`, by its shadow
    /// beam (exact), or where that beam ran past its budget, by the beam's exact part and rays over
    /// the rest.
    pub(super) fn beam_irradiance(&self, p: Vec3, n: Vec3, index: usize, rng: &mut Pcg32, t: &mut Thread) -> f32 {
        if !self.beams_pay() {
            return self.sampled_light(p, n, index, rng, t);
        }
        self.traced_irradiance(p, n, index, rng, t)
    }

    /// [`Context::beam_irradiance`] where beams pay. Not inlined: a point that samples its lights
    /// by rays (many small emitters) would pay for this one's frame on every light (9% of
    /// `spheres-256`'s shadow time).
    #[inline(never)]
    fn traced_irradiance(&self, p: Vec3, n: Vec3, index: usize, rng: &mut Pcg32, t: &mut Thread) -> f32 {
        let (ln, polygon) = (self.emitters[index].normal, self.emitters[index].polygon());
        // Exact shading: only the part of the light above the tangent plane lights the point.
        let mut polygon = match self.shading(index) {
            Shading::Exact => clip_above(polygon, p, n),
            Shading::Fraction => polygon.to_vec(),
        };
        if let Some(surface) = t.surface {
            polygon = clip_above(&polygon, p, surface);
        }
        if polygon.len() < 3 {
            return 0.0;
        }
        // In rays' worth of the light's own samples (a sky face's share of `--spp`).
        let samples = self.samples(p, n, index);
        if self.cut_outs_may_hide(p, &polygon, index, t) {
            // A texture's alpha cuts the light where no beam can: rays see through the cut-outs.
            t.c.shadow_beams += 1;
            t.c.cut_out_beams += 1;
            return self.sampled_whole(p, n, (index, samples), &polygon, rng, t);
        }
        if t.tile.candidates(index, t.block, p).is_some_and(|c| c.mode == Mode::Rays) {
            // The cluster samples this light from the start: no beam to set up.
            t.c.shadow_beams += 1;
            return self.sampled_whole(p, n, (index, samples), &polygon, rng, t);
        }
        let Some(beam) = light_beam(p, &polygon, ln) else { return 0.0 };
        t.c.shadow_beams += 1;
        let budget = if self.options.exact { u64::MAX } else { SPLITS_PER_RAY * u64::from(samples) };
        // Edges over the light a winding pass may weigh within the budget (its arrangement costs
        // about K² / 5 splits).
        let max_edges = if self.options.exact { usize::MAX } else { (5.0 * budget as f64).sqrt() as usize };
        let mut traced = ShadowBeam::new(&beam, &mut t.scratch).with_budget(budget);
        if !self.options.exact {
            traced = traced.with_contact();
        }
        let tris = &self.scene.triangles;
        let mut lit = None;
        let mut sample_all = false;
        match t.tile.candidates(index, t.block, p).map(|c| (c.cluster, c.mode)) {
            Some((cluster, mode)) => {
                let mut next = None;
                match mode {
                    Mode::Split => traced.occlude_packets(t.tile.packets(cluster), tris),
                    Mode::Walk => trace_bvh(&self.scene.bvh, tris, &mut traced),
                    Mode::Rays => unreachable!("sampled before the beam is set up"),
                    Mode::Winding => {
                        let edges = t.tile.edges(cluster, tris);
                        match traced.lit_by_winding(&beam.section, edges, tris, n, max_edges, &mut t.winding) {
                            Ok(l) => lit = Some(l),
                            // Past the budget (exact beams have none: past the arrangement's capacity).
                            Err(WindingError::Capacity) if !self.options.exact => sample_all = true,
                            Err(_) => {
                                traced.stats.silhouette_fallbacks += 1;
                                traced.occlude_packets(t.tile.packets(cluster), tris);
                            }
                        }
                    }
                    Mode::Probe => {
                        // Split first: where the candidates split the beam too little for the edges
                        // ever to pay ([`WindingWork::may_pay`]), the point says nothing of which way
                        // is cheaper, and the cluster's next beam probes again. Otherwise the edges
                        // too, once: the work of each decides the cluster's other beams.
                        let before = traced.stats;
                        let packets = t.tile.packets(cluster);
                        traced.occlude_packets(packets, tris);
                        let splits = traced.stats.intersections - before.intersections;
                        if WindingWork::may_pay(splits) {
                            let candidates = packets.iter().map(|q| q.len as usize).sum();
                            let before = traced.stats;
                            let edges = t.tile.edges(cluster, tris);
                            let result =
                                traced.lit_by_winding(&beam.section, edges, tris, n, max_edges, &mut t.winding);
                            let edges_over = traced.stats.silhouette_edges - before.silhouette_edges;
                            let work = WindingWork { records: edges.0.len(), reaching: edges.1.len(), edges_over };
                            let cheaper = result.is_ok() && work.cheaper_than(candidates, splits);
                            next = Some(if cheaper { Mode::Winding } else { Mode::Split });
                            lit = result.ok();
                        }
                    }
                }
                if sample_all || (lit.is_none() && traced.over_budget()) {
                    // Its neighbours would run past the budget too: they sample from the start.
                    next = Some(Mode::Rays);
                }
                if let Some(m) = next {
                    t.tile.decide(cluster, m);
                }
            }
            None => trace_bvh(&self.scene.bvh, tris, &mut traced),
        }
        t.c.beams += traced.stats;
        if traced.in_contact() {
            // A triangle touches the point: what it hides near the apex, rays find.
            t.c.contact_beams += 1;
            return self.sampled_whole(p, n, (index, samples), &polygon, rng, t);
        }
        let frame = traced.frame;
        if let Some(l) = lit {
            match self.shading(index) {
                Shading::Exact => l.irradiance.max(0.0),
                Shading::Fraction => self.fraction_irradiance(p, n, index, l.area / beam.area()),
            }
        } else {
            // Sampling from the start leaves the beam whole: its pieces are the light.
            let pieces = traced.pieces();
            let unresolved = sample_all || traced.over_budget();
            let unoccluded: f32 = match self.shading(index) {
                Shading::Exact => pieces.iter().map(|q| quad_irradiance(&frame, p, n, q)).sum(),
                Shading::Fraction => pieces.iter().map(Quad::area).sum::<f32>() / beam.area(),
            };
            if unresolved && unoccluded > 0.0 {
                let left = if sample_all { Left::Whole(&polygon) } else { Left::Pieces(&frame, pieces) };
                self.sampled(
                    (p, n, t.surface),
                    (index, samples),
                    (left, unoccluded),
                    rng,
                    (&mut t.c, t.partial.of(index)),
                )
            } else {
                match self.shading(index) {
                    Shading::Exact => unoccluded,
                    Shading::Fraction => self.fraction_irradiance(p, n, index, unoccluded),
                }
            }
        }
    }

    /// Whether a cut-out may hide part of `polygon`, light `index` clipped for `p`: one shaft test
    /// for the point's cluster (its candidates say, or the shaft from its box to the whole light,
    /// once), else for the point itself.
    pub(super) fn cut_outs_may_hide(&self, p: Vec3, polygon: &[Vec3], index: usize, t: &mut Thread) -> bool {
        let Some(cut_outs) = &self.cut_outs else { return false };
        let ln = self.emitters[index].normal;
        let Some(c) = t.tile.candidates(index, t.block, p) else {
            return cut_outs.may_hide(&Aabb::new(p, p), polygon, ln);
        };
        let (cluster, known, points) = (c.cluster, c.cut_outs, c.points);
        known.unwrap_or_else(|| {
            let hides = cut_outs.may_hide(&points, self.emitters[index].polygon(), ln);
            t.tile.set_cut_outs(cluster, hides);
            hides
        })
    }

    /// Irradiance per unit radiance at `p` (normal `n`) from area light `index` where beams do not
    /// pay ([`MIN_BEAM_SPP`]): the ray method's estimate from its `--spp` samples, counted as
    /// sampled; the estimate and the exact value both lie in `[0, bound]`, with the bound from
    /// [`irradiance_bound`](super::emitters::Emitter::irradiance_bound) (or the whole light's
    /// eq. 2). The ratio estimator would need the light's Lambert integral, which costs a point
    /// about four shadow rays here.
    fn sampled_light(&self, p: Vec3, n: Vec3, index: usize, rng: &mut Pcg32, t: &mut Thread) -> f32 {
        let clear = t.clear.sees_whole(index, t.block, p);
        if clear && self.options.spp > LAMBERT_RAYS {
            // Nothing lies between the point and the light: its unoccluded irradiance is exact.
            t.c.shadow_beams += 1;
            return match self.shading(index) {
                Shading::Exact => match t.surface {
                    Some(surface) => polygon_irradiance(p, n, &clip_above(self.emitters[index].polygon(), p, surface)),
                    None => polygon_irradiance(p, n, self.emitters[index].polygon()),
                },
                Shading::Fraction => self.fraction_irradiance(p, n, index, 1.0),
            };
        }
        let bound = match self.shading(index) {
            Shading::Exact => self.emitters[index].irradiance_bound(p),
            Shading::Fraction => self.fraction_irradiance(p, n, index, 1.0),
        };
        t.c.sampled_beams += 1;
        t.c.pending_bound += self.lights[index].power().max_element() * bound;
        self.ray_irradiance(p, n, index, clear, rng, t)
    }

    /// 001 eq. 2 for area light `index` with visible fraction `fraction`.
    pub(super) fn fraction_irradiance(&self, p: Vec3, n: Vec3, index: usize, fraction: f32) -> f32 {
        let e = &self.emitters[index];
        point_source_irradiance(p, n, e.center, e.normal, e.area, fraction.min(1.0))
    }

    /// Irradiance per unit radiance at `p` (normal `n`) from the part `polygon` of area light
    /// `index` above the point's tangent plane (the second argument is `(index, spp)`), all of it
    /// sampled: its exact unoccluded irradiance times the ratio estimate of its lit share
    /// ([`Context::seen_share`]), counted as a sampled beam with that irradiance as its bound.
    fn sampled_whole(
        &self,
        p: Vec3,
        n: Vec3,
        drawn: (usize, u32),
        polygon: &[Vec3],
        rng: &mut Pcg32,
        t: &mut Thread,
    ) -> f32 {
        let index = drawn.0;
        let unoccluded = match self.shading(index) {
            Shading::Exact => polygon_irradiance(p, n, polygon),
            Shading::Fraction => 1.0,
        };
        if !(unoccluded > 0.0) {
            return 0.0;
        }
        self.sampled((p, n, t.surface), drawn, (Left::Whole(polygon), unoccluded), rng, (&mut t.c, t.partial.of(index)))
    }

    /// Irradiance per unit radiance at `p` (normal `n`, surface normal `surface` under a normal
    /// texture, [`Thread::surface`]) from what is `left` of area light `index` to sample (the
    /// second argument is `(index, spp)`), whose unoccluded irradiance (or, with
    /// `--shading fraction`, area fraction) is `unoccluded`: that times the ratio estimate of its
    /// lit share ([`Context::seen_share`]), counted in `c` as a sampled beam with `unoccluded` as
    /// its bound.
    fn sampled(
        &self,
        (p, n, surface): (Vec3, Vec3, Option<Vec3>),
        (index, spp): (usize, u32),
        (left, unoccluded): (Left<'_>, f32),
        rng: &mut Pcg32,
        (c, partial): (&mut Counters, &mut bool),
    ) -> f32 {
        let seen = self.seen_share((p, n, surface), (index, spp), left, rng, (&mut c.shadow_rays, partial));
        c.sampled_beams += 1;
        c.pending_bound += self.lights[index].power().max_element() * unoccluded;
        match self.shading(index) {
            Shading::Exact => unoccluded * seen,
            Shading::Fraction => self.fraction_irradiance(p, n, index, unoccluded * seen),
        }
    }

    /// The ratio estimate of the lit share of what is `left` of light `index` seen from `p`
    /// (normal `n`; under a normal texture, nothing below the surface normal `surface`): the ray
    /// method's `spp` stratified samples of the light (the second argument is `(index, spp)`,
    /// [`Context::samples`]), those that fall in what is left each traced and
    /// weighted by the irradiance integrand `cos θ cos θ′ / r²`; the weight of those that reach
    /// the light over the weight of all (Heitz et al. 2018, the ratio estimator). The samples
    /// outside need no ray: the beam resolved them. 1 or 0 exactly when every traced sample is
    /// lit or every one hidden. Where the strata allow, they are drawn in rounds, which a first
    /// round whose rays all reach the light, or two whose rays all were stopped, end
    /// ([`draw_light`]).
    fn seen_share(
        &self,
        (p, n, surface): (Vec3, Vec3, Option<Vec3>),
        (index, spp): (usize, u32),
        left: Left<'_>,
        rng: &mut Pcg32,
        (shadow_rays, partial): (&mut u64, &mut bool),
    ) -> f32 {
        let light = &self.lights[index];
        let ln = self.emitters[index].normal;
        // With the whole light left, every sample falls in it.
        let bounds: Vec<(Vec2, Vec2)> = match left {
            Left::Whole(_) => Vec::new(),
            Left::Pieces(_, pieces) => pieces.iter().map(Quad::bounds).collect(),
        };
        let inside = |q: Vec3| match left {
            Left::Whole(_) => true,
            Left::Pieces(frame, pieces) => {
                let o = q - frame.origin;
                let uv = Vec2::new(o.dot(frame.u), o.dot(frame.v));
                pieces.iter().zip(&bounds).any(|(q, &(lo, hi))| {
                    uv.cmpge(lo).all() && uv.cmple(hi).all() && {
                        let n = q.len();
                        (0..n).all(|i| (q.corner((i + 1) % n) - q.corner(i)).perp_dot(uv - q.corner(i)) >= 0.0)
                    }
                })
            }
        };
        // A sample's integrand and whether it reaches the light (not traced where the integrand is 0).
        let mut last = None;
        let mut trace = |q: Vec3| -> (f64, bool) {
            let to = q - p;
            let r2 = to.length_squared();
            let w = to / r2.sqrt();
            let f = f64::from(n.dot(w).max(0.0) * (-ln).dot(w).max(0.0) / r2);
            // Below the surface itself, the beam's polygon has no part (its samples none).
            if !(f > 0.0) || surface.is_some_and(|s| s.dot(w) <= 0.0) {
                return (0.0, false);
            }
            *shadow_rays += 1;
            (f, !self.occluded((p, to), 1.0 - DEPTH_EPS, &mut last))
        };
        let mut tally = draw_light(spp, rng, partial, |(s, r), tally| {
            let q = sample_light(light, s, r);
            if inside(q) {
                let (f, seen) = trace(q);
                tally.add(f, seen);
            }
        });
        if tally.share().is_none() {
            // No sample fell in what is left (or none faces the point): one ray to its centre,
            // or its largest piece's.
            let centre = match left {
                Left::Whole(polygon) => Some(polygon.iter().sum::<Vec3>() / polygon.len() as f32),
                Left::Pieces(frame, pieces) => pieces
                    .iter()
                    .max_by(|a, b| a.area().total_cmp(&b.area()))
                    .map(|q| frame.point(q.corners().sum::<Vec2>() / q.len() as f32)),
            };
            if let Some(c) = centre {
                let (f, seen) = trace(c);
                tally.add(f, seen);
            }
        }
        tally.share().unwrap_or(0.0)
    }
}

/// What a shadow beam left of its light to sample.
#[derive(Clone, Copy)]
enum Left<'a> {
    /// All of it: the light's polygon above the point's tangent plane.
    Whole(&'a [Vec3]),
    /// The pieces on the light's plane (in the coordinates of the frame) the beam did not resolve.
    Pieces(&'a BeamFrame, &'a [Quad]),
}

/// Lambert's irradiance at `p` (normal `n`) from a piece on the plane of `frame`.
fn quad_irradiance(frame: &BeamFrame, p: Vec3, n: Vec3, q: &Quad) -> f32 {
    let mut corners = [Vec3::ZERO; 4];
    for (c, uv) in corners.iter_mut().zip(q.corners()) {
        *c = frame.point(uv);
    }
    polygon_irradiance(p, n, &corners[..q.len()])
}
