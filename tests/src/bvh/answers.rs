//! A layout's answers to a ray set, brute force's, and their comparison.

use super::brute_force::brute_force_closest;
use super::rays::RaySet;
use super::rounding::watertight_t_error;
use beam_bvh::{Bvh8, FlatBvh, Hit, WideBvh};
use beam_math::{Ray, Triangle};
use rayon::prelude::*;

/// A layout's answers: closest hits of camera and diffuse rays, any-hit answers of shadow rays.
pub(super) struct Answers<'a> {
    camera: Vec<Option<Hit>>,
    diffuse: Vec<Option<Hit>>,
    shadow: Vec<bool>,
    /// The triangles, when the answers were rounded otherwise than brute force's (the GPU's): their
    /// `t` is then compared within the rounding bound of [`t_tolerance`]. `None` for the CPU
    /// layouts, which run brute force's very arithmetic.
    rounded_otherwise: Option<&'a [Triangle]>,
}

impl<'a> Answers<'a> {
    pub(super) fn flat(bvh: &FlatBvh, triangles: &[Triangle], set: &RaySet) -> Self {
        let (rays, t_max) = shadow_rays(set);
        Self {
            camera: bvh.closest_hits(triangles, &set.camera, f32::INFINITY),
            diffuse: bvh.closest_hits(triangles, &set.diffuse, f32::INFINITY),
            shadow: bvh.any_hits(triangles, &rays, &t_max),
            rounded_otherwise: None,
        }
    }

    /// The GPU's answers: `bvh` in the GPU layout, traced by beam-gpu's compute ray tracer (its
    /// hits carry no barycentric weights, which [`compare`] does not read). The GPU's compiler may
    /// contract `a·b + c` into fused multiply-adds (NVIDIA's does; lavapipe's does not) and divide
    /// within 2.5 ULP, so its `t` is compared within the rounding bound.
    pub(super) fn gpu(
        gpu: &beam_gpu::Gpu,
        bvh: &FlatBvh,
        triangles: &'a [Triangle],
        set: &RaySet,
    ) -> Result<Self, String> {
        use beam_gpu::interface::MISS;
        use beam_gpu::raytrace::{GpuRay, RayTracer};
        let tracer = RayTracer::new(gpu, &beam_bvh::gpu::GpuBvh::new(bvh, triangles).map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())?;
        let closest = |rays: &[Ray]| -> Result<Vec<Option<Hit>>, String> {
            let hits =
                tracer.trace(gpu, &rays.iter().map(GpuRay::closest).collect::<Vec<_>>()).map_err(|e| e.to_string())?;
            Ok(hits.iter().map(|h| (h.prim != MISS).then_some(Hit { prim: h.prim, t: h.t, u: 0.0, v: 0.0 })).collect())
        };
        let shadow: Vec<GpuRay> = set.shadow.iter().map(|(r, t_max)| GpuRay::any(r, *t_max)).collect();
        Ok(Self {
            camera: closest(&set.camera)?,
            diffuse: closest(&set.diffuse)?,
            // An any-hit ray's t is 1 when occluded, 0 otherwise.
            shadow: tracer.trace(gpu, &shadow).map_err(|e| e.to_string())?.iter().map(|h| h.t > 0.5).collect(),
            rounded_otherwise: Some(triangles),
        })
    }

    pub(super) fn wide8(bvh: &Bvh8, set: &RaySet) -> Self {
        let (rays, t_max) = shadow_rays(set);
        Self {
            camera: bvh.closest_hits(&set.camera, f32::INFINITY),
            diffuse: bvh.closest_hits(&set.diffuse, f32::INFINITY),
            shadow: bvh.any_hits(&rays, &t_max),
            rounded_otherwise: None,
        }
    }

    pub(super) fn wide(bvh: &WideBvh, set: &RaySet) -> Self {
        let (rays, t_max) = shadow_rays(set);
        Self {
            camera: bvh.closest_hits(&set.camera, f32::INFINITY),
            diffuse: bvh.closest_hits(&set.diffuse, f32::INFINITY),
            shadow: bvh.any_hits(&rays, &t_max),
            rounded_otherwise: None,
        }
    }
}

fn shadow_rays(set: &RaySet) -> (Vec<Ray>, Vec<f32>) {
    (set.shadow.iter().map(|s| s.0).collect(), set.shadow.iter().map(|s| s.1).collect())
}

/// What a comparison with brute force accepted.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Agreement {
    /// Closest hits on another triangle at the same `t` (shared edges, coplanar faces).
    pub(super) ties: u64,
    /// Closest hits (and shadow rays' decisions near `t_max`) accepted only by the rounding bound
    /// (`|Δt|` beyond 1e-5 relative); always 0 for the CPU layouts.
    pub(super) widened: u64,
    /// The largest `|Δt|` of a closest hit as a fraction of its tolerance.
    pub(super) worst: f32,
}

impl std::ops::AddAssign for Agreement {
    fn add_assign(&mut self, other: Self) {
        self.ties += other.ties;
        self.widened += other.widened;
        self.worst = self.worst.max(other.worst);
    }
}

/// Relative tolerance on `t` for arithmetic that rounds as brute force does (the CPU layouts run
/// the very same f32 watertight test, so their closest hit on a triangle has brute force's `t` to
/// the bit; the slack only admits ties, hits on another triangle at the same `t`).
const SAME_ROUNDING: f32 = 1e-5;

/// How far a layout's `t` on triangle `got` may be from brute force's on triangle `want` (the same
/// triangle or a tie), for `ray` at brute force's `t`: `SAME_ROUNDING·t` for the CPU layouts; for
/// answers rounded otherwise (the GPU's: fused multiply-adds, divisions within 2.5 ULP) the larger
/// of that and the sum of the two evaluations' first-order rounding bounds ([`watertight_t_error`]
/// of the layout's triangle and of brute force's), so that a tie must still be one in exact
/// arithmetic as far as f32 can tell.
///
/// The bound is a condition estimate, not a fixed relative slack: about 1e-6 of `t` for the median
/// hit, but a few 1e-3 for a hit near the ray's origin on a triangle far larger than `t` (the edge
/// functions round in proportion to the triangle, `∂t/∂Uᵢ = (zᵢ − t)/det`) or for a grazing ray.
/// The H200's `t = 36.316822` against brute force's 36.31637 on the conference's 1,456-unit
/// triangle 3900 (exact 36.31702: brute force itself is 6.5e-4 off) is an FMA-contracted
/// evaluation (reproduced to the bit on the CPU with `mul_add`) within a tolerance of 1.7e-2. Over
/// the 2,000 camera and diffuse rays of each mesh the tolerance exceeds `SAME_ROUNDING·t` for
/// about 1% of the hits and is at most 5.8e-3 of `t` (sponza; sibenik 4.7e-3, conference 7.8e-4,
/// under 1e-4 on the other six meshes), while f32 evaluations with and without contraction stay
/// within a third of the bound of the exact `t`: a `t` off by 1e-2 of itself, or a farther
/// triangle at a `t` f32 can tell apart, still fails.
fn t_tolerance(rounded_otherwise: Option<&[Triangle]>, ray: Ray, t: f32, got: u32, want: u32) -> f32 {
    let same = SAME_ROUNDING * t.abs().max(1e-6);
    let Some(triangles) = rounded_otherwise else { return same };
    let bound = |prim: u32| watertight_t_error(ray, &triangles[prim as usize]).unwrap_or(0.0);
    same.max((bound(got) + bound(want)) as f32)
}

/// Compare one layout's answers with brute force: closest hits on the same triangle, or on another
/// at the same `t` (a tie), each within [`t_tolerance`] of brute force's `t`; shadow rays occluded
/// as brute force's closest hit says, unless that hit lies within the same tolerance of `t_max`.
pub(super) fn compare(
    name: &str,
    builder: &str,
    got: &Answers<'_>,
    set: &RaySet,
    reference: &Reference,
) -> Result<Agreement, String> {
    let mut agreement = Agreement::default();
    let rounded = got.rounded_otherwise;
    for (kind, rays, got, want) in [
        ("camera", &set.camera, &got.camera, &reference.camera),
        ("diffuse", &set.diffuse, &got.diffuse, &reference.diffuse),
    ] {
        for (i, (g, w)) in got.iter().zip(want.iter()).enumerate() {
            match (g, w) {
                (None, None) => {}
                (Some(g), Some(w)) => {
                    let tolerance = t_tolerance(rounded, rays[i], w.t, g.prim, w.prim);
                    let apart = (g.t - w.t).abs();
                    if !(apart <= tolerance) {
                        return Err(format!(
                            "{name} [{builder}] {kind} ray {i}: BVH t={} (triangle {}) vs brute force t={} (triangle {}); \
                             tolerance {tolerance:.1e}",
                            g.t, g.prim, w.t, w.prim
                        ));
                    }
                    agreement.ties += u64::from(g.prim != w.prim);
                    agreement.widened += u64::from(apart > SAME_ROUNDING * w.t.abs().max(1e-6));
                    agreement.worst = agreement.worst.max(apart / tolerance);
                }
                _ => {
                    return Err(format!(
                        "{name} [{builder}] {kind} ray {i}: BVH {g:?} vs brute force {w:?} for {:?}",
                        rays[i]
                    ));
                }
            }
        }
    }
    for (i, (g, w)) in got.shadow.iter().zip(reference.shadow.iter()).enumerate() {
        let (ray, t_max) = set.shadow[i];
        let want = w.is_some_and(|h| h.t <= t_max);
        let boundary = w.is_some_and(|h| (h.t - t_max).abs() <= t_tolerance(rounded, ray, t_max, h.prim, h.prim));
        if *g != want && !boundary {
            return Err(format!(
                "{name} [{builder}] shadow ray {i}: BVH occluded={g}, brute force {w:?} (t_max {t_max})"
            ));
        }
        agreement.widened += u64::from(*g != want && w.is_some_and(|h| (h.t - t_max).abs() > SAME_ROUNDING * t_max));
    }
    Ok(agreement)
}

/// Brute-force answers for a ray set.
pub(super) struct Reference {
    pub(super) camera: Vec<Option<Hit>>,
    diffuse: Vec<Option<Hit>>,
    shadow: Vec<Option<Hit>>,
}

pub(super) fn reference(triangles: &[Triangle], set: &RaySet) -> Reference {
    let closest = |rays: &[Ray]| {
        rays.par_iter().with_min_len(8).map(|r| brute_force_closest(triangles, *r, f32::INFINITY)).collect()
    };
    // A shadow ray's closest hit along the whole ray: whether it lies before `t_max`, or near
    // enough to it that either answer is right, is for `compare` to say.
    let shadow =
        set.shadow.par_iter().with_min_len(8).map(|(r, _)| brute_force_closest(triangles, *r, f32::INFINITY)).collect();
    Reference { camera: closest(&set.camera), diffuse: closest(&set.diffuse), shadow }
}
