//! The glossy light-volume renderer (002 §3–4): one eye ray per pixel centre, on through mirrors,
//! glass and thin panes by Whitted rays; every diffuse receiver point the eye reaches is lit by the
//! emitters directly (point lights, and area lights as stratified points: emitters.rs; occluders
//! other than scatterers by shadow rays, scatterers by the negative shadow beams) plus the
//! irradiance gathered from the scattered light beams. Its ground truth
//! ([`render_glossy_reference`]) shades the same points with exact shadow rays (area lights sampled
//! over their area, [`reference_direct`]) and the photon map of [`glossy_photons`].

use super::direct::{SKY_RAYS, reference_direct, sky_irradiance};
use super::kernel::PhotonKernel;
use super::photons::glossy_photons;
use crate::RenderError;
use crate::nonlinear::CpuBeams;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::glossy::{Emitter, Gathered, GlossyOptions, LightVolumes, Occluded, is_scatterer};
use beam_render::image::Image;
use beam_render::irradiance_map::IrradianceMap;
use beam_render::nonlinear::{BeamRenderer, Shade, ShadePoint, shade_by_waves};
use beam_render::tolerance::{DEPTH_EPS, shading_eps};
use beam_scene::region::PixelRect;
use beam_scene::scene::{Material, Scene};
use rayon::prelude::*;
use std::sync::PoisonError;
use std::time::Instant;

/// What a glossy render did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct GlossyStats {
    /// Wall time, seconds.
    pub seconds: f64,
    /// Seconds building the beams and their hierarchy.
    pub beam_seconds: f64,
    /// Seconds gathering.
    pub gather_seconds: f64,
    /// Scattered beams (specular and glossy).
    pub beams: u64,
    /// Negative shadow beams.
    pub shadow_beams: u64,
    /// Scatterer triangles skipped as degenerate (per light).
    pub degenerate: u64,
    /// Receiver points gathered.
    pub receivers: u64,
    /// Mean beams evaluated per receiver point (through the photon kernel, the splat's beam–block
    /// pairs count too).
    pub beams_per_point: f64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
}

/// Gathers many receiver points `(point, unit normal)` at once.
pub type Gather<'a> = dyn Fn(&LightVolumes, &[(Vec3, Vec3)]) -> Result<Vec<Gathered>, BackendError> + Sync + 'a;

/// The gather on the CPU, in parallel: through the hierarchy or over every beam; second-order
/// shadows by shadow rays through `scene` when `second_order`.
#[must_use]
pub fn gather_on_cpu(
    scene: &Scene,
    volumes: &LightVolumes,
    points: &[(Vec3, Vec3)],
    options: &GlossyOptions,
) -> Vec<Gathered> {
    let eps = shading_eps(scene);
    let occluded = occlusion(scene);
    points
        .par_iter()
        .map(|&(p, n)| {
            let q = p + n * eps;
            let occluded: Occluded<'_> = if options.second_order { Some(&occluded) } else { None };
            if options.hierarchy { volumes.gather(q, n, occluded) } else { volumes.gather_linear(q, n, occluded) }
        })
        .collect()
}

/// Second-order shadows: whether a shadow ray from a receiver point to a scatterer's source point
/// is blocked (stopping short of the source).
fn occlusion(scene: &Scene) -> impl Fn(Ray, f32) -> bool + Sync + '_ {
    let eps = shading_eps(scene);
    move |ray: Ray, t_max: f32| {
        let length = ray.direction.length() * t_max;
        length > eps && scene.occluded(ray, t_max * (1.0 - (2.0 * eps / length).max(DEPTH_EPS)))
    }
}

/// The scene must have a light that emits (002 traces beams from point sources; area lights are
/// taken as stratified points).
fn check_lights(scene: &Scene) -> Result<(), RenderError> {
    if beam_render::glossy::emitters(scene).is_empty() {
        return Err(RenderError::NoEmitters { scene: scene.name.clone() });
    }
    Ok(())
}

/// True when a diffuse receiver at `q` does not see the point light at `light` for an occluder that
/// is not a scatterer (scatterers shadow through their negative beams).
fn blocked_by_non_scatterers(scene: &Scene, q: Vec3, light: Vec3, eps: f32) -> bool {
    let mut o = q;
    for _ in 0..64 {
        let to = light - o;
        let Some(hit) = scene.closest_hit(Ray::new(o, to), 1.0 - DEPTH_EPS) else { return false };
        if !is_scatterer(&scene.material(hit.prim)) {
            return true;
        }
        o = o + to * hit.t + to.normalize_or_zero() * eps;
    }
    true
}

/// Unit normal of `prim` facing the arriving direction `d`.
fn facing(scene: &Scene, prim: u32, d: Vec3) -> Vec3 {
    let n = scene.normal(prim);
    if n.dot(d) < 0.0 { n } else { -n }
}

/// The normals of `s`: its triangle's facing the eye ([`facing`]), and the one its direct light's
/// cosines take (a normal texture's, [`Scene::mapped_normal`], as 001's shading takes it).
fn normals(scene: &Scene, s: &ShadePoint) -> [Vec3; 2] {
    let n = facing(scene, s.prim, s.d);
    [n, scene.mapped_normal(s.prim, s.p, n)]
}

/// Radiance of the eye's points `points` by `shade` for diffuse ones: mirrors, glass and thin panes
/// by Whitted rays through `renderer`, emitters their radiance, glossy reflectors their diffuse part
/// under direct light; an eye ray or Whitted ray that leaves the scene sees the environment, and eye
/// rays blend `BLEND` surfaces ([`eye_hits`]). Only the pixels of `region` (of the `width ×
/// height` frame) are traced, each seeded by its index in the frame, and the image holds just them.
fn render_points(
    scene: &Scene,
    (width, height): (u32, u32),
    region: PixelRect,
    renderer: &dyn BeamRenderer,
    diffuse: &Shade<'_>,
) -> Result<Image, BackendError> {
    let camera = scene.camera.with_size(width, height);
    let frame = camera.frame();
    let region = region.intersect(PixelRect::full(camera.width, camera.height));
    let rays: Vec<(usize, Ray)> =
        region.frame_indices(camera.width).map(|i| (i, camera.pixel_ray(&frame, i))).collect();
    let (seen, beyond) = eye_hits(scene, renderer, &rays)?;
    let shade = |batch: &[ShadePoint]| -> Result<Vec<Vec3>, BackendError> {
        let (receivers, others): (Vec<usize>, Vec<usize>) =
            (0..batch.len()).partition(|&i| matches!(scene.material(batch[i].prim), Material::Diffuse { .. }));
        let mut out = vec![Vec3::ZERO; batch.len()];
        let received: Vec<ShadePoint> = receivers.iter().map(|&i| batch[i]).collect();
        for (&i, c) in receivers.iter().zip(diffuse(&received)?) {
            out[i] = c;
        }
        for i in others {
            let s = &batch[i];
            out[i] = match scene.material(s.prim) {
                Material::Emissive { .. } => scene.emission_at(s.prim, s.p),
                Material::Glossy { .. } => {
                    scene.albedo_at(s.prim, s.p) / core::f32::consts::PI
                        * reference_direct(scene, s.p, normals(scene, s), s.seed)
                }
                _ => Vec3::ZERO,
            };
        }
        Ok(out)
    };
    let points: Vec<ShadePoint> = seen.iter().map(|s| s.2).collect();
    let radiance = shade_by_waves(scene, renderer, &shade, &points)?;
    let mut image = Image::new(region.width(), region.height());
    for ((pixel, &through), (_, ray)) in image.pixels.iter_mut().zip(&beyond).zip(&rays) {
        if through > 0.0 {
            *pixel = through * scene.environment.radiance(ray.direction);
        }
    }
    for ((k, share, _), c) in seen.into_iter().zip(radiance) {
        image.pixels[k] += share * c;
    }
    Ok(image)
}

/// A surface an eye ray sees: the ray's index, the surface's share of its radiance, its point.
type Seen = (usize, f32, ShadePoint);

/// What the eye's `rays` (pixel index in the frame, ray) see: per surface, the ray's index, its
/// share of the ray's radiance and its point; and per ray the share that leaves the scene. A ray
/// sees the nearest surface by `renderer`, or, in a scene with cut-outs, every `BLEND` surface it
/// meets blended front to back as `beam` and `ray` blend them ([`Scene::blended_hits`]).
fn eye_hits(
    scene: &Scene,
    renderer: &dyn BeamRenderer,
    rays: &[(usize, Ray)],
) -> Result<(Vec<Seen>, Vec<f32>), BackendError> {
    let point = |i: usize, ray: Ray, h: Hit| ShadePoint {
        prim: h.prim,
        p: ray.at(h.t),
        d: ray.direction.normalize(),
        seed: i as u64,
    };
    if scene.has_cut_outs() {
        let blended: Vec<(Vec<Seen>, f32)> = rays
            .par_iter()
            .enumerate()
            .map(|(k, &(i, ray))| {
                let mut seen = Vec::new();
                let beyond = scene.blended_hits(ray, f32::INFINITY, |h, share| seen.push((k, share, point(i, ray, h))));
                (seen, beyond)
            })
            .collect();
        let beyond = blended.iter().map(|b| b.1).collect();
        return Ok((blended.into_iter().flat_map(|b| b.0).collect(), beyond));
    }
    let hits = renderer.closest_hits(scene, &rays.iter().map(|r| r.1).collect::<Vec<_>>())?;
    let beyond = hits.iter().map(|h| if h.is_none() { 1.0 } else { 0.0 }).collect();
    let seen = hits.iter().zip(rays).enumerate().filter_map(|(k, (h, &(i, ray)))| Some((k, 1.0, point(i, ray, (*h)?))));
    Ok((seen.collect(), beyond))
}

/// Direct irradiance at `p` (unit normal `n`, cosines with the `shading` normal as
/// [`reference_direct`] takes them) from the `emitters` not in mask `shadowed` (their shadow beams
/// cover `p`): occluders that are not scatterers cast shadows by shadow rays.
fn direct(scene: &Scene, emitters: &[Emitter], p: Vec3, [n, shading]: [Vec3; 2], shadowed: u64) -> Vec3 {
    let eps = shading_eps(scene);
    let q = p + n * eps;
    let mut e = Vec3::ZERO;
    for (l, emitter) in emitters.iter().enumerate() {
        let to = emitter.position - q;
        let r2 = to.length_squared();
        let d = to / r2.sqrt();
        let (cos, falloff) = (shading.dot(d), emitter.falloff(-d));
        if !(n.dot(d) > 0.0 && cos > 0.0 && falloff > 0.0) || shadowed & (1 << l.min(63)) != 0 {
            continue;
        }
        if !blocked_by_non_scatterers(scene, q, emitter.position, eps) {
            e += emitter.intensity * (falloff * cos / r2);
        }
    }
    e
}

/// Render `scene` by glossy light volumes on the CPU.
pub fn render_glossy(scene: &Scene, options: &GlossyOptions) -> Result<(Image, GlossyStats), RenderError> {
    let gather = |v: &LightVolumes, points: &[(Vec3, Vec3)]| Ok(gather_on_cpu(scene, v, points, options));
    render_glossy_with(scene, options, &CpuBeams, &gather)
}

/// Render `scene` by glossy light volumes: beams built on the CPU (in parallel), eye rays traced by
/// `renderer`, receiver points gathered by `gather` (the CPU's, or a GPU's).
pub fn render_glossy_with(
    scene: &Scene,
    options: &GlossyOptions,
    renderer: &dyn BeamRenderer,
    gather: &Gather<'_>,
) -> Result<(Image, GlossyStats), RenderError> {
    check_lights(scene)?;
    let start = Instant::now();
    let volumes = LightVolumes::new(scene, options.method, options.subdivide);
    let beam_seconds = start.elapsed().as_secs_f64();
    // Through the photon map's kernel: the scattered beams splatted into the map once, the shadow
    // beams still gathered per point (without scattered beams, the plain gather does the same).
    let t = Instant::now();
    let scattered = volumes.beams.iter().any(|b| !b.shadow);
    let splatted = (options.filter > 0.0 && scattered).then(|| {
        let occluded = occlusion(scene);
        let occluded: Occluded<'_> = if options.second_order { Some(&occluded) } else { None };
        let (maps, tested) = PhotonKernel::new(scene, options.filter).splat(&volumes, occluded);
        (maps, volumes.shadows(), tested)
    });
    let totals = std::sync::Mutex::new((t.elapsed().as_secs_f64(), 0u64, splatted.as_ref().map_or(0, |s| s.2)));
    let diffuse = |points: &[ShadePoint]| -> Result<Vec<Vec3>, BackendError> {
        let at: Vec<(Vec3, Vec3)> = points.iter().map(|s| (s.p, facing(scene, s.prim, s.d))).collect();
        let t = Instant::now();
        let gathered = match &splatted {
            Some((maps, shadows, _)) => {
                let eps = shading_eps(scene);
                points
                    .par_iter()
                    .zip(&at)
                    .map(|(s, &(p, n))| Gathered {
                        irradiance: maps.irradiance(s.prim, p, s.d),
                        ..shadows.gather(p + n * eps, n, None)
                    })
                    .collect()
            }
            None => gather(&volumes, &at)?,
        };
        if let Ok(mut totals) = totals.lock() {
            totals.0 += t.elapsed().as_secs_f64();
            totals.1 += points.len() as u64;
            totals.2 += gathered.iter().map(|g| u64::from(g.tested)).sum::<u64>();
        }
        Ok(points
            .par_iter()
            .zip(&at)
            .zip(gathered)
            .map(|((s, &(p, _)), g)| {
                let normals = normals(scene, s);
                let sky = sky_irradiance(scene, p, normals, s.seed, SKY_RAYS);
                scene.albedo_at(s.prim, s.p) / core::f32::consts::PI
                    * (direct(scene, &volumes.emitters, p, normals, g.shadowed) + sky + g.irradiance)
            })
            .collect())
    };
    let image = render_points(scene, (options.width, options.height), options.region(), renderer, &diffuse)?;
    // Nothing panics while holding the lock: a poisoned one still holds the right totals.
    let (gather_seconds, receivers, tested) = totals.into_inner().unwrap_or_else(PoisonError::into_inner);
    let shadow_beams = volumes.beams.iter().filter(|b| b.shadow).count() as u64;
    let stats = GlossyStats {
        seconds: start.elapsed().as_secs_f64(),
        beam_seconds,
        gather_seconds,
        beams: volumes.beams.len() as u64 - shadow_beams,
        shadow_beams,
        degenerate: volumes.degenerate,
        receivers,
        beams_per_point: tested as f64 / receivers.max(1) as f64,
        width: image.width,
        height: image.height,
    };
    Ok((image, stats))
}

/// The ground truth of [`render_glossy`]: the same eye paths, receivers lit directly with exact
/// shadow rays (every occluder; area lights sampled over their area, [`reference_direct`]) plus
/// the scattered light of `map` (from [`glossy_photons`]).
pub fn render_glossy_photons(
    scene: &Scene,
    width: u32,
    height: u32,
    map: &IrradianceMap,
) -> Result<Image, RenderError> {
    render_glossy_photons_in(scene, (width, height), PixelRect::full(width, height), map)
}

/// [`render_glossy_photons`] of the pixels of `region` only (of the `width × height` frame), each
/// as in the whole frame.
pub fn render_glossy_photons_in(
    scene: &Scene,
    (width, height): (u32, u32),
    region: PixelRect,
    map: &IrradianceMap,
) -> Result<Image, RenderError> {
    check_lights(scene)?;
    let diffuse = |points: &[ShadePoint]| -> Result<Vec<Vec3>, BackendError> {
        Ok(points
            .par_iter()
            .map(|s| {
                let e = reference_direct(scene, s.p, normals(scene, s), s.seed) + map.irradiance(s.prim, s.p, s.d);
                scene.albedo_at(s.prim, s.p) / core::f32::consts::PI * e
            })
            .collect())
    };
    Ok(render_points(scene, (width, height), region, &CpuBeams, &diffuse)?)
}

/// [`render_glossy_photons`] with a fresh photon map of about `photons` photons per light.
pub fn render_glossy_reference(
    scene: &Scene,
    width: u32,
    height: u32,
    photons: u64,
    seed: u64,
) -> Result<Image, RenderError> {
    render_glossy_reference_in(scene, (width, height), PixelRect::full(width, height), photons, seed)
}

/// [`render_glossy_reference`] of the pixels of `region` only (of the `width × height` frame), each
/// as in the whole frame; the photon map is still the whole scene's.
pub fn render_glossy_reference_in(
    scene: &Scene,
    size: (u32, u32),
    region: PixelRect,
    photons: u64,
    seed: u64,
) -> Result<Image, RenderError> {
    check_lights(scene)?;
    render_glossy_photons_in(scene, size, region, &glossy_photons(scene, photons, seed))
}
