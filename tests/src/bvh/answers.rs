//! A layout's answers to a ray set, brute force's, and their comparison.

use super::brute_force::brute_force_closest;
use super::rays::RaySet;
use beam_bvh::{Bvh8, FlatBvh, Hit, WideBvh};
use beam_math::{Ray, Triangle};
use rayon::prelude::*;

/// A layout's answers: closest hits of camera and diffuse rays, any-hit answers of shadow rays.
pub(super) struct Answers {
    camera: Vec<Option<Hit>>,
    diffuse: Vec<Option<Hit>>,
    shadow: Vec<bool>,
}

impl Answers {
    pub(super) fn flat(bvh: &FlatBvh, triangles: &[Triangle], set: &RaySet) -> Self {
        let (rays, t_max) = shadow_rays(set);
        Self {
            camera: bvh.closest_hits(triangles, &set.camera, f32::INFINITY),
            diffuse: bvh.closest_hits(triangles, &set.diffuse, f32::INFINITY),
            shadow: bvh.any_hits(triangles, &rays, &t_max),
        }
    }

    /// The GPU's answers: `bvh` in the GPU layout, traced by beam-gpu's compute ray tracer (its
    /// hits carry no barycentric weights, which [`compare`] does not read).
    pub(super) fn gpu(
        gpu: &beam_gpu::Gpu,
        bvh: &FlatBvh,
        triangles: &[Triangle],
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
        })
    }

    pub(super) fn wide8(bvh: &Bvh8, set: &RaySet) -> Self {
        let (rays, t_max) = shadow_rays(set);
        Self {
            camera: bvh.closest_hits(&set.camera, f32::INFINITY),
            diffuse: bvh.closest_hits(&set.diffuse, f32::INFINITY),
            shadow: bvh.any_hits(&rays, &t_max),
        }
    }

    pub(super) fn wide(bvh: &WideBvh, set: &RaySet) -> Self {
        let (rays, t_max) = shadow_rays(set);
        Self {
            camera: bvh.closest_hits(&set.camera, f32::INFINITY),
            diffuse: bvh.closest_hits(&set.diffuse, f32::INFINITY),
            shadow: bvh.any_hits(&rays, &t_max),
        }
    }
}

fn shadow_rays(set: &RaySet) -> (Vec<Ray>, Vec<f32>) {
    (set.shadow.iter().map(|s| s.0).collect(), set.shadow.iter().map(|s| s.1).collect())
}

/// Compare one layout's answers with brute force; returns the number of ties accepted.
pub(super) fn compare(
    name: &str,
    builder: &str,
    got: &Answers,
    set: &RaySet,
    reference: &Reference,
) -> Result<u64, String> {
    let mut ties = 0;
    for (kind, rays, got, want) in [
        ("camera", &set.camera, &got.camera, &reference.camera),
        ("diffuse", &set.diffuse, &got.diffuse, &reference.diffuse),
    ] {
        for (i, (g, w)) in got.iter().zip(want.iter()).enumerate() {
            match (g, w) {
                (None, None) => {}
                (Some(g), Some(w)) => {
                    let close = (g.t - w.t).abs() <= 1e-5 * w.t.abs().max(1e-6);
                    if !close {
                        return Err(format!(
                            "{name} [{builder}] {kind} ray {i}: BVH t={} (triangle {}) vs brute force t={} (triangle {})",
                            g.t, g.prim, w.t, w.prim
                        ));
                    }
                    if g.prim != w.prim {
                        ties += 1;
                    }
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
        let t_max = set.shadow[i].1;
        let want = w.is_some_and(|h| h.t <= t_max);
        let boundary = w.is_some_and(|h| (h.t - t_max).abs() <= 1e-5 * t_max);
        if *g != want && !boundary {
            return Err(format!(
                "{name} [{builder}] shadow ray {i}: BVH occluded={g}, brute force {w:?} (t_max {t_max})"
            ));
        }
    }
    Ok(ties)
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
    let shadow = set
        .shadow
        .par_iter()
        .with_min_len(8)
        .map(|(r, t)| brute_force_closest(triangles, *r, t * (1.0 + 1e-5)))
        .collect();
    Reference { camera: closest(&set.camera), diffuse: closest(&set.diffuse), shadow }
}
