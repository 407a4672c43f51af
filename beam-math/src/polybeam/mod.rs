//! Polygon beams of 001: an apex and a convex cross-section on a reference plane, split exactly by
//! triangles into hit and miss beams.

mod beam;
mod merge;
mod quad;
mod split;
mod winding;

pub use beam::{BeamFrame, MAX_CORNERS, PolyBeam, Section};
pub use merge::merge;
pub use quad::{Cover, EdgeLines, Line, MAX_EDGES, Quad};
pub use split::{KEEP_CORNERS, Part, Pieces, ProjectedTriangle, Split, split_section};
pub use winding::{
    Arrangement, MAX_WINDING_EDGES, WindingEdge, WindingError, orient2d, winding_after, zero_winding_boundary,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::Triangle;
    use glam::Vec3;

    fn eye_beam() -> PolyBeam {
        let frame = BeamFrame::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0), Vec3::Z, Vec3::X).unwrap();
        let corners = [
            Vec3::new(-1.0, -1.0, 1.0),
            Vec3::new(1.0, -1.0, 1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(-1.0, 1.0, 1.0),
        ];
        PolyBeam::new(frame, &corners).unwrap()
    }

    #[test]
    fn triangle_inside_the_beam_splits_into_hit_and_three_misses() {
        let beam = eye_beam();
        assert_eq!(beam.area(), 4.0);
        // A triangle at depth 2 whose projection is (−0.5,−0.5), (0.5,−0.5), (0,0.5).
        let tri = Triangle::new(Vec3::new(-1.0, -1.0, 2.0), Vec3::new(1.0, -1.0, 2.0), Vec3::new(0.0, 1.0, 2.0));
        let s = beam.split(&tri, 1e-3, f32::INFINITY, 1e-6).unwrap();
        assert!((s.hit.area() - 0.5).abs() < 1e-5, "{}", s.hit.area());
        assert!((s.hit.area() + s.miss.area() - 4.0).abs() < 1e-4);
        assert_eq!(s.miss.len(), 3);
    }

    #[test]
    fn trivial_cases() {
        let beam = eye_beam();
        let far_away = Triangle::new(Vec3::new(5.0, 5.0, 1.0), Vec3::new(6.0, 5.0, 1.0), Vec3::new(5.0, 6.0, 1.0));
        let s = beam.split(&far_away, 1e-3, f32::INFINITY, 1e-6).unwrap();
        assert!(s.hit.is_empty() && s.miss.len() == 1);
        let covering =
            Triangle::new(Vec3::new(-10.0, -10.0, 1.0), Vec3::new(10.0, -10.0, 1.0), Vec3::new(0.0, 10.0, 1.0));
        let s = beam.split(&covering, 1e-3, f32::INFINITY, 1e-6).unwrap();
        assert!(s.miss.is_empty() && (s.hit.area() - 4.0).abs() < 1e-5);
        // Behind the far limit (a shadow beam ending at depth 1): missed.
        let behind =
            Triangle::new(Vec3::new(-10.0, -10.0, 3.0), Vec3::new(10.0, -10.0, 3.0), Vec3::new(0.0, 10.0, 3.0));
        assert!(beam.split(&behind, 1e-3, 1.0, 1e-6).unwrap().hit.is_empty());
    }

    #[test]
    fn triangle_crossing_the_apex_plane_is_clipped() {
        let beam = eye_beam();
        // From behind the apex to in front: only the front part can be hit.
        let tri = Triangle::new(Vec3::new(-0.2, -0.2, -1.0), Vec3::new(0.2, -0.2, -1.0), Vec3::new(0.0, 0.2, 3.0));
        let s = beam.split(&tri, 1e-3, f32::INFINITY, 1e-6).unwrap();
        assert!((s.hit.area() + s.miss.area() - 4.0).abs() < 1e-3);
    }

    /// A sliver met on the conference room: a polygon within a few tolerances of a point, all its
    /// edges too short to have a direction, hides nothing (skipping them once gave a hit part of
    /// the section's whole length).
    #[test]
    fn point_like_triangles_hide_nothing() {
        use crate::collide::ConvexPolygon;
        use glam::Vec2;
        let v = |p: &[(f32, f32)]| p.iter().map(|&(x, y)| Vec2::new(x, y)).collect::<Vec<_>>();
        let section = Section::from_slice(&v(&[
            (-0.379_592_9, 0.178_272_22),
            (-0.385_949_46, 0.263_592_8),
            (-0.386_745_93, 0.264_530_36),
            (-0.385_162_35, 0.214_532_67),
        ]))
        .unwrap();
        let sliver = v(&[(-0.385_160_83, 0.214_532_38), (-0.385_162_35, 0.214_532_61), (-0.385_160_86, 0.214_527_17)]);
        let polygon = ConvexPolygon::from_slice(&sliver).unwrap();
        let (min, max) = polygon.bounds();
        let projected = ProjectedTriangle { polygon, min, max };
        let mut area = 0.0;
        split_section(&section, &projected, 1e-5, &mut |part, s| {
            area += s.area();
            if part == Part::Hit {
                for c in s.vertices() {
                    let out = (min - *c).max(*c - max).max_element();
                    assert!(out < 1e-6, "hit corner {c} outside the sliver {min}–{max}");
                }
            }
        })
        .unwrap();
        assert!((area - section.area()).abs() < 1e-6 * section.area().max(1e-3));
    }
}
