//! The host's shading of points, for what a renderer hands back: [`HostShading`], and
//! [`shade_points`] by a renderer or else the host.

use super::renderer::PointShading;
use super::texture::ShadePoint;
use crate::BackendError;
use crate::irradiance_map::IrradianceMap;
use crate::options::RenderOptions;
use beam_math::glam::Vec3;
use beam_scene::scene::Scene;

/// Shades points on the host: a frame's fallback for the points its renderer does not shade
/// ([`PointShading::shade_points`](super::PointShading::shade_points) answering `None`). beam-cpu's
/// `CpuBeams` is one: its `shade_point`, every area light exact.
pub trait HostShading: Sync {
    /// The radiance of every point with `options`, the caustics read from `caustics`.
    fn shade_on_host(
        &self,
        scene: &Scene,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Vec<Vec3>;
}

/// The radiance of every point: by `renderer` where it shades with `options`, else by `host`.
pub fn shade_points<R: PointShading + ?Sized>(
    renderer: &mut R,
    host: &dyn HostShading,
    scene: &Scene,
    options: &RenderOptions,
    caustics: Option<&IrradianceMap>,
    points: &[ShadePoint],
) -> Result<Vec<Vec3>, BackendError> {
    Ok(match renderer.shade_points(scene, options, caustics, points)? {
        Some(radiance) => radiance,
        None => host.shade_on_host(scene, options, caustics, points),
    })
}
