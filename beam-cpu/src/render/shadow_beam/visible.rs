//! The visible part of a light from a point: the beam from the point to the light, traced to the
//! end through the BVH.

use super::{BeamStats, ShadowBeam, ShadowScratch, trace_bvh};
use beam_bvh::FlatBvh;
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_math::polybeam::{BeamFrame, PolyBeam, Section};

/// The visible part of a light polygon from a point, as convex pieces on the light's plane.
#[derive(Clone, Debug)]
pub struct VisibleLight {
    /// Apex (the shade point) and the light plane.
    pub frame: BeamFrame,
    /// Unoccluded pieces, in the light plane's coordinates.
    pub pieces: Vec<Section>,
    /// Area of the whole light polygon.
    pub light_area: f32,
}

impl VisibleLight {
    /// Visible fraction of the light's area.
    #[must_use]
    pub fn fraction(&self) -> f32 {
        if self.light_area > 0.0 {
            (self.pieces.iter().map(Section::area).sum::<f32>() / self.light_area).min(1.0)
        } else {
            0.0
        }
    }

    /// The visible pieces as 3D polygons on the light.
    #[must_use]
    pub fn polygons(&self) -> Vec<Vec<Vec3>> {
        self.pieces.iter().map(|s| s.vertices().iter().map(|&c| self.frame.point(c)).collect()).collect()
    }
}

/// The part of `light` (a convex polygon, 3 to 8 corners) visible from `p`. `None` when `p` lies on
/// the light's plane or behind it.
pub fn visible_light(
    bvh: &FlatBvh,
    triangles: &[Triangle],
    p: Vec3,
    light: &[Vec3],
    light_normal: Vec3,
    stats: &mut BeamStats,
) -> Option<VisibleLight> {
    let beam = light_beam(p, light, light_normal)?;
    Some(visible_section(bvh, triangles, &beam, stats))
}

/// The beam from `p` to `light` (its reference plane the light's), or `None` when `p` lies on the
/// light's plane or behind it.
pub(crate) fn light_beam(p: Vec3, light: &[Vec3], light_normal: Vec3) -> Option<PolyBeam> {
    if light.len() < 3 || light_normal.dot(p - light[0]) <= 0.0 {
        return None;
    }
    let frame = BeamFrame::new(p, light[0], light_normal, light[1] - light[0])?;
    PolyBeam::new(frame, light)
}

/// The part of `beam`'s cross-section seen from its apex past every triangle strictly between the
/// apex and the reference plane (depths in `[DEPTH_EPS, 1 − DEPTH_EPS]`).
pub(crate) fn visible_section(
    bvh: &FlatBvh,
    triangles: &[Triangle],
    beam: &PolyBeam,
    stats: &mut BeamStats,
) -> VisibleLight {
    let mut scratch = ShadowScratch::default();
    let mut traced = ShadowBeam::new(beam, &mut scratch);
    trace_bvh(bvh, triangles, &mut traced);
    *stats += traced.stats;
    let pieces = traced
        .pieces()
        .iter()
        .map(|q| {
            let mut section = Section::new();
            // A quad's 3 or 4 corners always fit a section.
            q.corners().for_each(|c| section.push(c).unwrap_or_default());
            section
        })
        .collect();
    VisibleLight { frame: beam.frame, pieces, light_area: beam.area() }
}
