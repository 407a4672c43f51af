//! The ray-traced ground truth of the nonlinear renderer: Whitted rays through mirrors and glass
//! about the interpolated (Phong) normals, the smooth surfaces the S mesh stands for, traced in
//! waves so that a GPU's ray tracer can find every wave's hits at once.

use super::caustics::caustics_by_photons;
use super::trace::{BeamRenderer, CpuBeams};
use crate::render::{Image, MAX_DEPTH, RenderOptions, shade_point, shading_eps, specular_rays};
use crate::scene::Scene;
use beam_math::Ray;
use beam_math::glam::Vec3;
use rayon::prelude::*;

/// A path of the Whitted reference: its pixel, its next ray and its weight.
type Path = (usize, Ray, Vec3);

/// The ray-traced ground truth of [`super::render_nonlinear`] on the CPU (see
/// [`render_smooth_reference_with`]).
#[must_use]
pub fn render_smooth_reference(scene: &Scene, options: &RenderOptions, photons: u64) -> Image {
    render_smooth_reference_with(scene, options, photons, &CpuBeams)
        .unwrap_or_else(|e| unreachable!("the CPU ray tracer failed: {e}"))
}

/// The ray-traced ground truth of [`super::render_nonlinear`]: one ray per pixel centre, Whitted
/// through mirrors and glass (at most [`MAX_DEPTH`] bounces) about the interpolated normals;
/// caustics by about `photons` photons per point light ([`caustics_by_photons`]); everything else
/// shaded alike. The rays of each bounce are traced together by `renderer`.
pub fn render_smooth_reference_with(
    scene: &Scene,
    options: &RenderOptions,
    photons: u64,
    renderer: &dyn BeamRenderer,
) -> Result<Image, String> {
    let caustics = caustics_by_photons(scene, photons, options.seed);
    let camera = scene.camera.with_size(options.width, options.height);
    let frame = camera.frame();
    let eps = shading_eps(scene);
    let mut image = Image::new(camera.width, camera.height);
    let mut paths: Vec<Path> = (0..image.pixels.len()).map(|i| (i, camera.pixel_ray(&frame, i), Vec3::ONE)).collect();
    for depth in 0..=MAX_DEPTH {
        if paths.is_empty() {
            break;
        }
        let rays: Vec<Ray> = paths.iter().map(|p| p.1).collect();
        let hits = renderer.closest_hits(scene, &rays)?;
        // Per path: the paths it continues as, and the radiance it adds to its pixel.
        let next: Vec<(Vec<Path>, (usize, Vec3))> = paths
            .par_iter()
            .zip(hits)
            .map(|(&(px, ray, weight), hit)| {
                let Some(hit) = hit else { return (Vec::new(), (px, Vec3::ZERO)) };
                let (p, d) = (ray.at(hit.t), ray.direction.normalize());
                match specular_rays(scene, eps, hit.prim, p, d) {
                    Some(_) if depth == MAX_DEPTH => (Vec::new(), (px, Vec3::ZERO)),
                    Some(scattered) => {
                        (scattered.into_iter().flatten().map(|(r, k)| (px, r, weight * k)).collect(), (px, Vec3::ZERO))
                    }
                    None => {
                        let radiance = shade_point(scene, options, caustics.as_ref(), hit.prim, p, d, px as u64);
                        (Vec::new(), (px, weight * radiance))
                    }
                }
            })
            .collect();
        paths = Vec::new();
        for (more, (px, radiance)) in next {
            image.pixels[px] += radiance;
            paths.extend(more);
        }
    }
    Ok(image)
}
