//! The eye's half of the wavefront: the camera rays of a band of rows, then the mirror and glass
//! rays they send on, each generation one batch of closest hits. A ray that leaves the scene brings
//! the environment's radiance to its pixel, one that meets an emitter the emission; one that meets
//! a diffuse or glossy surface leaves a shade point for the light stage.

use super::batches::closest_hits;
use super::eye::EYE_SAMPLES;
use crate::render::eye_regions::Region;
use crate::render::renderer::context::{Context, pixel_seed};
use crate::render::renderer::shading::stratified;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::queries::{BeamQueries, PixelFragments};
use beam_render::specular::{MAX_DEPTH, specular_rays};
use beam_scene::scene::{Camera, Material};
use rand::SeedableRng;
use rand_pcg::Pcg32;
use rayon::prelude::*;

/// A ray of the wavefront and where its radiance goes.
#[derive(Clone, Copy, Debug)]
struct PathRay {
    ray: Ray,
    /// Its camera sample: index in the band's camera rays, `primary_spp` a pixel, row-major.
    sample: u32,
    /// Its place in its camera sample's tree of bounces ([`child_key`]).
    key: u32,
    /// Mirror and glass bounces behind it.
    depth: u32,
    /// Weight of its radiance in its pixel: the box filter's `1 / primary_spp` times the specular
    /// weights on its way.
    weight: Vec3,
}

/// A diffuse or glossy point a camera sample's path found, to gather direct light at.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadePoint {
    /// The gather point: the surface point offset off the surface on the viewer's side.
    pub(super) p: Vec3,
    /// The unit shading normal, facing the viewer: the surface's, or where a normal texture bends
    /// it ([`Scene::mapped_normal`](beam_scene::scene::Scene::mapped_normal)), the bent one.
    pub(super) n: Vec3,
    /// Under a normal texture, the surface's own unit normal (facing the viewer): what lies below
    /// its plane the surface hides ([`Thread::surface`](crate::render::renderer::context::Thread)).
    pub(super) surface: Option<Vec3>,
    /// The surface's albedo there.
    pub(super) albedo: Vec3,
    /// Weight of its radiance in its pixel.
    pub(super) weight: Vec3,
    /// Its camera sample.
    pub(super) sample: u32,
    /// Its place in the sample's tree of bounces: the sample's shade points in this order are
    /// the order in which the CPU renderer's depth-first recursion shades them.
    pub(super) key: u32,
}

/// What the shade points of a band are to be lit for, and what the band got without them.
pub(super) struct Band {
    /// The band's pixels with the environment's and the emitters' radiance, row-major.
    pub(super) pixels: Vec<Vec3>,
    /// The shade points, by camera sample and, within one, in depth-first order.
    pub(super) points: Vec<ShadePoint>,
    /// Rays traced (camera, mirror and glass rays).
    pub(super) rays: u64,
}

impl Band {
    /// Take what ray `r` found: light into its pixel, a shade point, or its rays into `next`.
    fn take(&mut self, r: PathRay, f: Found, per_pixel: u32, next: &mut Vec<PathRay>) {
        match f {
            Found::Light(l) => self.pixels[(r.sample / per_pixel) as usize] += r.weight * l,
            Found::Point(s) => self.points.push(s),
            Found::Rays(children) => next.extend(children.into_iter().flatten()),
            Found::Dark => {}
        }
    }
}

/// What a ray found.
enum Found {
    /// Radiance for its pixel.
    Light(Vec3),
    /// A point to light.
    Point(ShadePoint),
    /// The rays a mirror or glass sends on.
    Rays([Option<PathRay>; 2]),
    /// Nothing (a specular surface past [`MAX_DEPTH`]).
    Dark,
}

/// The key of child `c` (0 or 1, in [`specular_rays`]' order) of the ray whose key is `key`, the
/// child `depth` bounces deep (1 to [`MAX_DEPTH`]): a binary digit a level, the first level most
/// significant, so that keys in increasing order visit a tree's leaves depth first.
fn child_key(key: u32, depth: u32, c: u32) -> u32 {
    key | c << (MAX_DEPTH - depth)
}

/// How the eye sees a band: `k × k` stratified camera rays a pixel, or every pixel's exact
/// fragments (eye beams; the whole frame's, row-major).
#[derive(Clone, Copy)]
pub(super) enum Primary<'a> {
    Rays(u32),
    Fragments(&'a [PixelFragments]),
}

impl Primary<'_> {
    /// Camera samples a pixel (their indices divided by this give the pixel).
    pub(super) fn per_pixel(&self) -> u32 {
        match self {
            Primary::Rays(k) => k * k,
            Primary::Fragments(_) => EYE_SAMPLES,
        }
    }
}

/// The camera rays of `band` (`k × k` stratified rays a pixel, jittered and seeded as the CPU
/// renderer's primary rays are), or its pixels' fragments (each a centroid ray that meets its
/// triangle's plane there, weighted by its coverage; the background's centroid ray brings the
/// environment), and the rays after them, traced by `backend` a generation at a time.
pub(super) fn trace_band(
    ctx: &Context<'_>,
    camera: &Camera,
    backend: &dyn BeamQueries,
    band: Region,
    primary: Primary<'_>,
) -> Result<Band, BackendError> {
    let scene = ctx.scene;
    let frame = camera.frame();
    let per_pixel = primary.per_pixel();
    let mut out = Band { pixels: vec![Vec3::ZERO; band.len()], points: Vec::new(), rays: 0 };
    let mut rays: Vec<PathRay> = match primary {
        Primary::Rays(k) => {
            let weight = Vec3::splat(1.0 / per_pixel as f32);
            (0..band.len() as u32)
                .into_par_iter()
                .flat_map_iter(|i| {
                    let (x, y) = (band.x0 + i % band.width(), band.y0 + i / band.width());
                    let mut rng = Pcg32::seed_from_u64(pixel_seed(ctx.options.seed, x, y));
                    (0..per_pixel).map(move |j| {
                        let (jx, jy) = stratified(j, k, &mut rng);
                        let ray = camera.ray(&frame, x as f32 + jx, y as f32 + jy);
                        PathRay { ray, sample: i * per_pixel + j, key: 0, depth: 0, weight }
                    })
                })
                .collect()
        }
        Primary::Fragments(view) => {
            // The first generation's hits are known: each fragment's triangle, where its centroid
            // ray meets the triangle's plane.
            let first: Vec<(PathRay, Found)> = (0..band.len() as u32)
                .into_par_iter()
                .flat_map_iter(|i| {
                    let (x, y) = (band.x0 + i % band.width(), band.y0 + i / band.width());
                    let seen = &view[(y * camera.width + x) as usize];
                    let background = {
                        let c = seen.background_centroid;
                        let ray = camera.ray(&frame, c.x, c.y);
                        let r = PathRay {
                            ray,
                            sample: i * per_pixel + per_pixel - 1,
                            key: 0,
                            depth: 0,
                            weight: Vec3::splat(seen.background),
                        };
                        (r, Found::Light(scene.environment.radiance(ray.direction)))
                    };
                    let fragments = seen.fragments.iter().enumerate().filter_map(move |(j, f)| {
                        let ray = camera.ray(&frame, f.centroid.x, f.centroid.y);
                        let tri = scene.triangles.get(f.prim as usize)?;
                        let n = tri.scaled_normal();
                        let t = n.dot(tri.v[0] - ray.origin) / n.dot(ray.direction);
                        if !(t.is_finite() && t > 0.0) {
                            return None;
                        }
                        let hit = Hit::on(tri, f.prim, &ray, t);
                        let sample = i * per_pixel + (j as u32).min(per_pixel - 2);
                        let r = PathRay { ray, sample, key: 0, depth: 0, weight: Vec3::splat(f.coverage) };
                        Some((r, follow(ctx, &r, Some(&hit))))
                    });
                    fragments.chain((seen.background > 0.0).then_some(background))
                })
                .collect();
            out.rays += first.len() as u64;
            let mut next = Vec::new();
            for (r, f) in first {
                out.take(r, f, per_pixel, &mut next);
            }
            next
        }
    };
    while !rays.is_empty() {
        let batch: Vec<Ray> = rays.iter().map(|r| r.ray).collect();
        let hits = closest_hits(backend, scene, &batch)?;
        out.rays += rays.len() as u64;
        let found: Vec<Found> = rays.par_iter().zip(&hits).map(|(r, hit)| follow(ctx, r, hit.as_ref())).collect();
        let mut next = Vec::new();
        for (r, f) in rays.iter().zip(found) {
            out.take(*r, f, per_pixel, &mut next);
        }
        rays = next;
    }
    out.points.par_sort_unstable_by_key(|s| (s.sample, s.key));
    Ok(out)
}

/// What ray `r` found at `hit` (as [`Context::radiance`] and [`Context::shade`] take it).
fn follow(ctx: &Context<'_>, r: &PathRay, hit: Option<&Hit>) -> Found {
    let scene = ctx.scene;
    let Some(hit) = hit else { return Found::Light(scene.environment.radiance(r.ray.direction)) };
    let (q, d) = (r.ray.at(hit.t), r.ray.direction.normalize());
    if let Some((p, facing)) = ctx.gather_point(hit.prim, q, d) {
        let albedo = scene.albedo_at(hit.prim, q);
        // Lit as `Context::shade` lights it: by the bent normal, above the surface's own plane too.
        let n = scene.mapped_normal(hit.prim, q, facing);
        let surface = (n != facing).then_some(facing);
        return Found::Point(ShadePoint { p, n, surface, albedo, weight: r.weight, sample: r.sample, key: r.key });
    }
    match scene.material(hit.prim) {
        Material::Emissive { .. } => Found::Light(scene.emission_at(hit.prim, q)),
        _ if r.depth < MAX_DEPTH => match specular_rays(scene, ctx.eps, hit.prim, q, d) {
            Some(sent) => {
                let mut children = [None; 2];
                for (c, (ray, w)) in sent.into_iter().flatten().enumerate() {
                    let depth = r.depth + 1;
                    let key = child_key(r.key, depth, c as u32);
                    children[c] = Some(PathRay { ray, sample: r.sample, key, depth, weight: r.weight * w });
                }
                Found::Rays(children)
            }
            None => Found::Dark,
        },
        _ => Found::Dark,
    }
}
