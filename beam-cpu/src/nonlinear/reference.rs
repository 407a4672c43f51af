//! The ray-traced ground truth of the nonlinear renderer: Whitted rays through mirrors and glass
//! about the interpolated (Phong) normals, the smooth surfaces the S mesh stands for, traced in
//! waves so that a GPU's ray tracer can find every wave's hits at once.

use super::cpu_beams::CpuBeams;
use crate::RenderError;
use beam_math::glam::Vec3;
use beam_render::image::Image;
use beam_render::nonlinear::{BeamRenderer, HostShading, Path, ShadePoint, caustics_by_photons, trace_waves};
use beam_render::options::RenderOptions;
use beam_scene::scene::Scene;

/// The ray-traced ground truth of [`super::render_nonlinear`] on the CPU (see
/// [`render_smooth_reference_with`]).
#[must_use]
pub fn render_smooth_reference(scene: &Scene, options: &RenderOptions, photons: u64) -> Image {
    render_smooth_reference_with(scene, options, photons, &CpuBeams)
        .unwrap_or_else(|e| unreachable!("the CPU ray tracer failed: {e}"))
}

/// The ray-traced ground truth of [`super::render_nonlinear`]: one ray per pixel centre, Whitted
/// through mirrors and glass (at most [`MAX_DEPTH`](beam_render::specular::MAX_DEPTH) bounces) about the interpolated normals;
/// caustics by about `photons` photons per light ([`caustics_by_photons`]); everything else
/// shaded alike. The rays of each bounce are traced together by `renderer`. Only the pixels of
/// `options.region` are traced (the photons are the whole scene's).
pub fn render_smooth_reference_with(
    scene: &Scene,
    options: &RenderOptions,
    photons: u64,
    renderer: &dyn BeamRenderer,
) -> Result<Image, RenderError> {
    let caustics = caustics_by_photons(scene, photons, options.seed);
    let camera = scene.camera.with_size(options.width, options.height);
    let frame = camera.frame();
    let crop = options.region();
    let mut pixels = vec![Vec3::ZERO; camera.width as usize * camera.height as usize];
    let paths: Vec<Path> =
        crop.frame_indices(camera.width).map(|i| (i, camera.pixel_ray(&frame, i), Vec3::ONE)).collect();
    // The ground truth shades exactly, on the CPU.
    let shade = |points: &[ShadePoint]| Ok(CpuBeams.shade_on_host(scene, options, caustics.as_ref(), points));
    trace_waves(scene, renderer, &shade, &|i| i as u64, paths, 0, &mut pixels)?;
    Ok(Image { width: crop.width(), height: crop.height(), pixels: crop.cut(pixels, camera.width) })
}
