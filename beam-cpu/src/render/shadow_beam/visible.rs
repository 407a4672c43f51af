//! The visible part of a light from a point: the beam from the point to the light, traced to the
//! end through the BVH.

use super::walk::trace_bvh;
use super::{BeamStats, ShadowBeam, ShadowScratch};
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

#[cfg(test)]
mod tests {
    use super::*;
    use beam_bvh::BuildOptions;
    use beam_math::polybeam::Quad;
    use beam_render::tolerance::DEPTH_EPS;

    /// The unit square at z = 2, facing −z.
    fn square_light() -> [Vec3; 4] {
        [Vec3::new(-0.5, -0.5, 2.0), Vec3::new(0.5, -0.5, 2.0), Vec3::new(0.5, 0.5, 2.0), Vec3::new(-0.5, 0.5, 2.0)]
    }

    #[test]
    fn clipped_triangles_hide_what_the_clipped_projection_covers() {
        // Triangles reaching behind the point and past the light, against the independent clip of
        // beam-math (ProjectedTriangle: 3D Sutherland–Hodgman, then projection).
        use beam_math::collide::ConvexPolygon;
        use beam_math::polybeam::ProjectedTriangle;
        let light = square_light();
        let beam = light_beam(Vec3::ZERO, &light, -Vec3::Z).unwrap();
        let mut s = 99u32;
        let mut r = move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        let mut clipped = 0;
        for _ in 0..3000 {
            let tri = Triangle::new(
                Vec3::new(r(), r(), 1.0 + 2.0 * r()),
                Vec3::new(r(), r(), 1.0 + 2.0 * r()),
                Vec3::new(r(), r(), 1.0 + 2.0 * r()),
            );
            let mut scratch = ShadowScratch::default();
            let mut traced = ShadowBeam::new(&beam, &mut scratch);
            traced.occlude(&tri);
            let visible: f32 = traced.pieces().iter().map(Quad::area).sum();
            let hidden = ProjectedTriangle::new(&beam.frame, &tri, DEPTH_EPS, 1.0 - DEPTH_EPS).map_or(0.0, |p| {
                let poly = ConvexPolygon::<16>::from_slice(p.polygon.vertices()).unwrap();
                poly.clip_by(&beam.section).unwrap().area()
            });
            clipped += usize::from(tri.v.iter().any(|v| v.z < 0.0 || v.z > 2.0));
            // Corners clipped at the near plane project ~1/DEPTH_EPS times farther out, where f32
            // rounding of either clip is ~1e-4 of the light.
            assert!((visible + hidden - 1.0).abs() < 1e-3, "{tri:?}: visible {visible}, hidden {hidden}");
        }
        assert!(clipped > 1000, "{clipped}");
    }

    /// A triangle in the plane `x + y = c` reaching from behind the point past the light projects
    /// into a sliver on the far side of the line `x + y = c` on the light's plane (depth 2 and
    /// nearer, scaled by 2 / depth ≥ 1), whose bounding rectangle covers the light: at c = 1.2 it
    /// misses the unit light, whose corner reaches x + y = 1, and is dropped before any piece is
    /// split; at c = 0.8 it hides the corner beyond x + y = 0.8.
    #[test]
    fn a_sliver_beside_the_light_is_dropped_unsplit() {
        let light = square_light();
        let beam = light_beam(Vec3::ZERO, &light, -Vec3::Z).unwrap();
        let diagonal = |c: f32| {
            let v = |x: f32, z: f32| Vec3::new(x, c - x, z);
            Triangle::new(v(5.0, -1.0), v(c - 5.0, -1.0), v(0.5 * c, 3.0))
        };
        let occlude = |tri: Triangle| {
            let mut scratch = ShadowScratch::default();
            let mut traced = ShadowBeam::new(&beam, &mut scratch);
            let hit = traced.occlude(&tri);
            (hit, traced.stats.intersections, traced.pieces().iter().map(Quad::area).sum::<f32>())
        };
        assert_eq!(occlude(diagonal(1.2)), (false, 0, 1.0));
        let (hit, splits, visible) = occlude(diagonal(0.8));
        assert!(hit && splits > 0, "{hit} {splits}");
        // The corner beyond x + y = 0.8: a right triangle with legs 0.2.
        assert!((visible - (1.0 - 0.02)).abs() < 1e-4, "{visible}");
    }

    #[test]
    fn square_occluder_parallel_to_square_light() {
        // Light: unit square at z = 2; occluder: square of half-width 0.125 at z = 1 centred above
        // the origin, whose shadow on the light plane from the origin has half-width 0.25.
        let light = square_light();
        let h = 0.125;
        let occ = vec![
            Triangle::new(Vec3::new(-h, -h, 1.0), Vec3::new(h, -h, 1.0), Vec3::new(h, h, 1.0)),
            Triangle::new(Vec3::new(-h, -h, 1.0), Vec3::new(h, h, 1.0), Vec3::new(-h, h, 1.0)),
        ];
        let bvh = FlatBvh::build(&occ, &BuildOptions::sah());
        let mut stats = BeamStats::default();
        // Shadow of the occluder on the light plane: half-width 2h = 0.25, area 0.25 of the light.
        let v = visible_light(&bvh, &occ, Vec3::ZERO, &light, -Vec3::Z, &mut stats).unwrap();
        assert!((v.fraction() - 0.75).abs() < 1e-5, "{}", v.fraction());
        assert!(v.pieces.iter().all(|p| p.len() <= 4));
        // Shifted sideways by x: the shadow moves by −x·(2−1)/1 = −x on the light plane.
        let v = visible_light(&bvh, &occ, Vec3::new(0.1, 0.0, 0.0), &light, -Vec3::Z, &mut stats).unwrap();
        assert!((v.fraction() - 0.75).abs() < 1e-5);
        // At x = 0.6 the shadow's centre is at 0.6 − 2·0.6 = −0.6: it covers x ∈ [−0.85, −0.35], of
        // which [−0.5, −0.35] is on the light: area 0.15 × 0.5.
        let v = visible_light(&bvh, &occ, Vec3::new(0.6, 0.0, 0.0), &light, -Vec3::Z, &mut stats).unwrap();
        assert!((v.fraction() - (1.0 - 0.15 * 0.5)).abs() < 1e-4, "{}", v.fraction());
        assert!(stats.bvh_steps > 0 && stats.intersections > 0 && stats.triangle_tests > 0);
    }

    /// A triangle that crosses the beam within its near plane of the point (before depth
    /// `DEPTH_EPS` of the light's distance) is a contact, which rays starting at the point would
    /// find; one that passes beside or behind the point, or meets the beam only farther on, is not.
    #[test]
    fn a_triangle_through_the_point_is_a_contact() {
        let light = square_light();
        let beam = light_beam(Vec3::ZERO, &light, -Vec3::Z).unwrap();
        let contact = |tri: Triangle| {
            let mut scratch = ShadowScratch::default();
            let mut traced = ShadowBeam::new(&beam, &mut scratch).with_contact();
            traced.occlude(&tri);
            traced.in_contact()
        };
        let big = |z: &dyn Fn(f32, f32) -> f32| {
            let v = |x: f32, y: f32| Vec3::new(x, y, z(x, y));
            Triangle::new(v(-1.0, -1.0), v(2.0, -1.0), v(-1.0, 2.0))
        };
        // Wholly before the near plane (2e-4), over the point: a contact, which the near plane alone
        // would have dropped.
        assert!(contact(big(&|_, _| 1e-5)));
        // A steep plane passing 1e-5 beside the point: rays to the light's side x < 0.25 cross it
        // at depth 2e-5 / (2 − 8x), most of them before the near plane.
        assert!(contact(big(&|x, _| 8.0 * x + 1e-5)));
        // A plane through the point that leaves the whole beam on one side (z = 0.5x: the beam's
        // rays have z ≥ 4|x|): rays from the point never cross it.
        assert!(!contact(big(&|x, _| 0.5 * x)));
        // Just behind the point (the surface it lies on): none.
        assert!(!contact(big(&|_, _| -1e-5)));
        // A wall 0.3 to the side: it meets the beam only past depth 1.2.
        let wall = Triangle::new(Vec3::new(0.3, -1.0, -1.0), Vec3::new(0.3, 1.0, -1.0), Vec3::new(0.3, 0.0, 3.0));
        assert!(!contact(wall));
        // A plane just below the point that leans away from the light: every ray to the light
        // stays above it.
        assert!(!contact(big(&|x, _| -x - 1e-5)));
    }
}
