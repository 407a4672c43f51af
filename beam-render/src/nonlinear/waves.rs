//! Whitted rays past the beam tree, traced in waves so that a backend finds every wave's hits at
//! once: mirror and glass points continue as their specular rays (at most [`MAX_DEPTH`] bounces),
//! the points the paths end on are shaded in one batch per wave.

use super::texture::ShadePoint;
use crate::error::BackendError;
use crate::parallel::par_flatten;
use crate::queries::RayQueries;
use crate::specular::{MAX_DEPTH, specular_rays};
use crate::tolerance::shading_eps;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_scene::scene::Scene;
use rayon::prelude::*;

/// A path of the Whitted reference: its pixel, its next ray and its weight.
pub type Path = (usize, Ray, Vec3);

/// The radiance of every point, as beam-cpu's `shade_point` would compute it, with `shade` for the
/// diffuse, glossy and emissive ones (all of them in one batch) and mirror and glass points followed
/// by Whitted rays traced in waves through `renderer`, the points they end on shaded by `shade` in
/// one batch per wave.
pub fn shade_by_waves(
    scene: &Scene,
    renderer: &(impl RayQueries + ?Sized),
    shade: &Shade<'_>,
    points: &[ShadePoint],
) -> Result<Vec<Vec3>, BackendError> {
    let eps = shading_eps(scene);
    // Per point, its specular rays (mirror and glass) or `None` (shaded where it is); in parallel,
    // in the points' order.
    let scattered: Vec<_> = points.par_iter().map(|s| specular_rays(scene, eps, s.prim, s.p, s.d)).collect();
    let direct: Vec<usize> = gather(&scattered, 0, |i, s| [s.is_none().then_some(i), None]);
    let paths: Vec<Path> =
        gather(&scattered, NO_PATH, |i, rays| rays.unwrap_or_default().map(|s| s.map(|(r, k)| (i, r, k))));
    let mut out = vec![Vec3::ZERO; points.len()];
    let batch: Vec<ShadePoint> = direct.par_iter().map(|&i| points[i]).collect();
    for (&i, radiance) in direct.iter().zip(shade(&batch)?) {
        out[i] = radiance;
    }
    // A point reached through mirrors and glass draws its samples from the seed of the point it was
    // reached from (not from that point's place in `points`), so that every point's radiance is the
    // same whatever else is in the batch (a tile of an image shades as the whole image does).
    trace_waves(scene, renderer, shade, &|i| points[i].seed, paths, 1, &mut out)?;
    Ok(out)
}

/// Where a path ends: its pixel, its weight and the point it hit.
type End = (usize, Vec3, ShadePoint);

/// Shades a batch of diffuse, glossy or emissive points.
pub type Shade<'a> = dyn Fn(&[ShadePoint]) -> Result<Vec<Vec3>, BackendError> + Sync + 'a;

/// Trace `paths` (at bounce `first` of at most [`MAX_DEPTH`]) wave by wave: each wave's nearest hits
/// by `renderer`, mirror and glass hits continuing as their [`specular_rays`], every other hit
/// shaded by `shade` in one batch (drawing its samples from the seed `seed(pixel)`) and added, times
/// its path's weight, to `out[pixel]`; a path that leaves the scene adds the environment's radiance
/// along its ray.
pub fn trace_waves(
    scene: &Scene,
    renderer: &(impl RayQueries + ?Sized),
    shade: &Shade<'_>,
    seed: &(dyn Fn(usize) -> u64 + Sync),
    mut paths: Vec<Path>,
    first: u32,
    out: &mut [Vec3],
) -> Result<(), BackendError> {
    let eps = shading_eps(scene);
    for depth in first..=MAX_DEPTH {
        if paths.is_empty() {
            break;
        }
        let rays: Vec<Ray> = paths.par_iter().map(|p| p.1).collect();
        let hits = renderer.closest_hits(scene, &rays)?;
        // Per path: the (at most two) paths it continues as, or the point it ends on.
        let next: Vec<([Option<Path>; 2], Option<End>)> = paths
            .par_iter()
            .zip(&hits)
            .map(|(&(px, ray, weight), &hit)| {
                let Some(hit) = hit else { return ([None; 2], None) };
                let (p, d) = (ray.at(hit.t), ray.direction.normalize());
                match specular_rays(scene, eps, hit.prim, p, d) {
                    Some(_) if depth == MAX_DEPTH => ([None; 2], None),
                    Some(scattered) => (scattered.map(|s| s.map(|(r, k)| (px, r, weight * k))), None),
                    None => ([None; 2], Some((px, weight, ShadePoint { prim: hit.prim, p, d, seed: seed(px) }))),
                }
            })
            .collect();
        if !scene.environment.is_black() {
            for (&(px, ray, weight), hit) in paths.iter().zip(&hits) {
                if hit.is_none() {
                    out[px] += weight * scene.environment.radiance(ray.direction);
                }
            }
        }
        let ends: Vec<End> = gather(&next, (0, Vec3::ZERO, ShadePoint::default()), |_, (_, e)| [*e, None]);
        let points: Vec<ShadePoint> = ends.par_iter().map(|e| e.2).collect();
        for ((px, weight, _), radiance) in ends.iter().zip(shade(&points)?) {
            out[*px] += *weight * radiance;
        }
        paths = gather(&next, NO_PATH, |_, (more, _)| *more);
    }
    Ok(())
}

/// A placeholder of [`par_flatten`]'s output before it is filled.
const NO_PATH: Path = (0, Ray { origin: Vec3::ZERO, direction: Vec3::ZERO }, Vec3::ZERO);

/// What `each(i, &items[i])` holds (at most two items), for every `i` in order, flattened by every
/// thread ([`par_flatten`]).
fn gather<S: Sync, T: Copy + Send + Sync>(
    items: &[S],
    placeholder: T,
    each: impl Fn(usize, &S) -> [Option<T>; 2] + Sync,
) -> Vec<T> {
    par_flatten(
        items,
        placeholder,
        |i, s| each(i, s).iter().flatten().count(),
        |i, s, push| each(i, s).into_iter().flatten().for_each(push),
    )
}
