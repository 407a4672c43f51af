//! The radiance flow of a beam tree (000 §7.3, the final composite): deepest level first, every
//! texel that hit is shaded, or, on a specular S-mesh face with child beams, textured from the
//! children's radiance at the face's barycentric point (bilinear, Fresnel-weighted for glass), and
//! every texel whose ray left the scene shows the environment; the eye's pixels last.
//! [`composite_levels`] does it on the CPU; beam-gpu's renderer keeps every level's radiance on
//! the GPU and reads back only the pixels.

use super::radiance::{LevelRadiance, composite, sample_region};
use super::smesh::SMesh;
use super::texture::ShadePoint;
use crate::BackendError;
use beam_math::glam::Vec3;
use beam_scene::scene::Scene;
use rayon::prelude::*;

/// The radiance flow on the CPU: `levels[0]` is the eye's view, `levels[k]` the tree's level k;
/// deepest first, each level's points without a composite shaded by `shade` in one batch (a
/// backend's shading, which may keep what it uploads for the next batch), the
/// others composited from the level below. Returns the eye's pixels.
pub fn composite_levels(
    scene: &Scene,
    smesh: &SMesh,
    levels: &[LevelRadiance],
    mut shade: impl FnMut(&[ShadePoint]) -> Result<Vec<Vec3>, BackendError>,
) -> Result<Vec<Vec3>, BackendError> {
    let mut below: Vec<Vec3> = Vec::new();
    let mut below_regions: &[(u32, u32)] = &[];
    for level in levels.iter().rev() {
        let points: Vec<ShadePoint> = level.texels.iter().filter(|t| t.composite.is_none()).map(|t| t.point).collect();
        let mut shaded = shade(&points)?.into_iter();
        let sample = |beam: u32, w: Vec3| {
            let (first, size) = below_regions[beam as usize];
            let region = below.get(first as usize..).unwrap_or_default();
            sample_region(region, size, w)
        };
        let composited: Vec<Option<Vec3>> =
            level.texels.par_iter().map(|t| Some(composite(scene, smesh, &t.point, t.composite?, sample))).collect();
        let mut out = vec![Vec3::ZERO; level.len];
        for &(t, d) in &level.missed {
            out[t as usize] = scene.environment.radiance(d);
        }
        for (t, c) in level.texels.iter().zip(composited) {
            out[t.texel as usize] = c.or_else(|| shaded.next()).unwrap_or_default();
        }
        below = out;
        below_regions = &level.regions;
    }
    Ok(below)
}
