//! Exact visibility of a polygonal light from a point (001 §5): a beam from the shade point to the
//! light polygon traverses the BVH; at every leaf each remaining piece of the light is split exactly
//! at the triangle's edges (001 §3.2); the miss pieces are the visible part of the light.
//!
//! The order of occluders does not matter for visibility (any triangle between the point and the
//! light blocks), so hit pieces are dropped at once instead of traversing on. A BVH references each
//! triangle from exactly one leaf, so the kd-tree mailboxing of 001 §3.4 has nothing to remove here.

use beam_bvh::{Control, FlatBvh, NodeVisitor};
use beam_math::collide::aabb_outside_planes;
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, Part, PolyBeam, ProjectedTriangle, Section, split_section};
use beam_math::{Aabb, Triangle};

/// Occluders are counted only strictly between the point and the light: depths (in units of the
/// light-plane distance) within `[DEPTH_EPS, 1 − DEPTH_EPS]`.
pub const DEPTH_EPS: f32 = 1e-4;

/// Work done by beams (eye or shadow beams).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BeamStats {
    /// BVH nodes tested against the beam frustum (001's "BVH steps").
    pub bvh_steps: u64,
    /// Beam–triangle split operations (001's "intersections").
    pub intersections: u64,
    /// Hit pieces produced (001's "hit beams").
    pub hit_beams: u64,
}

impl core::ops::AddAssign for BeamStats {
    fn add_assign(&mut self, o: Self) {
        self.bvh_steps += o.bvh_steps;
        self.intersections += o.intersections;
        self.hit_beams += o.hit_beams;
    }
}

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

/// A remaining piece of the light with its bounding rectangle.
#[derive(Clone, Copy)]
struct LitPiece {
    section: Section,
    lo: Vec2,
    hi: Vec2,
}

impl LitPiece {
    fn new(section: Section) -> Self {
        let (lo, hi) = section.bounds();
        Self { section, lo, hi }
    }
}

struct ShadowVisitor<'a> {
    triangles: &'a [Triangle],
    frame: BeamFrame,
    pieces: Vec<LitPiece>,
    /// Miss parts of the piece being split (scratch).
    misses: Vec<Section>,
    /// Bounding rectangle of the remaining pieces on the light plane.
    lo: Vec2,
    hi: Vec2,
    /// Outward normals of the four planes through the apex and the rectangle's sides, then the
    /// near and far planes (`depth = DEPTH_EPS`, `depth = 1 − DEPTH_EPS`) as (normal, offset).
    planes: [(Vec3, f32); 6],
    stats: BeamStats,
}

impl ShadowVisitor<'_> {
    /// Recompute the bounding rectangle of the pieces and the beam planes around it.
    fn update_bounds(&mut self) {
        (self.lo, self.hi) =
            self.pieces.iter().fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), p| (lo.min(p.lo), hi.max(p.hi)));
        let f = &self.frame;
        let apex = f.apex;
        for (plane, n) in self.planes.iter_mut().zip(f.side_normals(self.lo, self.hi)) {
            *plane = (n, n.dot(apex));
        }
        // Depth d(x) = (x − apex)·N / distance: near plane keeps d ≥ ε, far plane keeps d ≤ 1 − ε.
        let n = f.normal / f.distance;
        self.planes[4] = (-n, -n.dot(apex) - DEPTH_EPS);
        self.planes[5] = (n, n.dot(apex) + 1.0 - DEPTH_EPS);
    }

    /// Split every piece the projected triangle overlaps, in place: a piece is replaced by its miss
    /// parts (hit parts are occluded and dropped). True when any piece was hit.
    fn occlude(&mut self, projected: &ProjectedTriangle) -> bool {
        let mut hit = false;
        // Pieces [0, end) are the ones from before this triangle; its miss parts are appended.
        let mut end = self.pieces.len();
        let mut i = 0;
        while i < end {
            if !projected.overlaps(self.pieces[i].lo, self.pieces[i].hi) {
                i += 1;
                continue;
            }
            let piece = self.pieces[i];
            self.stats.intersections += 1;
            let mut hits = 0;
            self.misses.clear();
            let (misses, hits_ref) = (&mut self.misses, &mut hits);
            let emitted = split_section(&piece.section, projected, 1e-6, &mut |part, s| match part {
                Part::Hit => *hits_ref += 1,
                Part::Miss => misses.push(s),
            });
            // Untouched, or a piece that outgrew its corner capacity (kept whole, visible).
            if hits == 0 || emitted.is_err() {
                i += 1;
                continue;
            }
            hit = true;
            self.stats.hit_beams += hits;
            match self.misses.split_first() {
                Some((first, rest)) => {
                    self.pieces[i] = LitPiece::new(*first);
                    self.pieces.extend(rest.iter().map(|&s| LitPiece::new(s)));
                    i += 1;
                }
                None => {
                    // Wholly hidden: move the last unvisited piece here, then drop this one.
                    end -= 1;
                    self.pieces.swap(i, end);
                    self.pieces.swap_remove(end);
                }
            }
        }
        hit
    }
}

impl NodeVisitor for ShadowVisitor<'_> {
    /// A node is entered unless its box lies wholly outside one of the beam's six planes (the four
    /// through the apex and the sides of the pieces' bounding rectangle, the near and far planes),
    /// tested at the box corner nearest to the inside: the plane test of frustum culling, cheap and
    /// conservative (001 §3.3 keeps near and far planes per axis for the same purpose).
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        self.stats.bvh_steps += 1;
        if aabb_outside_planes(bounds, &self.planes) {
            return None;
        }
        Some(0.0)
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        for &p in prims {
            // Depth clipping only: shadow beams can graze the light's plane, where planes through the
            // apex and the window are nearly parallel to it and clipping by them is ill-conditioned.
            let Some(projected) =
                ProjectedTriangle::new(&self.frame, &self.triangles[p as usize], DEPTH_EPS, 1.0 - DEPTH_EPS)
            else {
                continue;
            };
            if !projected.overlaps(self.lo, self.hi) {
                continue;
            }
            if self.occlude(&projected) {
                if self.pieces.is_empty() {
                    return Control::Stop;
                }
                // Pieces only shrink where the triangle hit one; otherwise the bounds still hold.
                self.update_bounds();
            }
        }
        Control::Continue
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
    if light.len() < 3 || light_normal.dot(p - light[0]) <= 0.0 {
        return None;
    }
    let frame = BeamFrame::new(p, light[0], light_normal, light[1] - light[0])?;
    Some(visible_section(bvh, triangles, &PolyBeam::new(frame, light)?, stats))
}

/// The part of `beam`'s cross-section seen from its apex past every triangle strictly between the
/// apex and the reference plane (depths in `[DEPTH_EPS, 1 − DEPTH_EPS]`).
pub fn visible_section(bvh: &FlatBvh, triangles: &[Triangle], beam: &PolyBeam, stats: &mut BeamStats) -> VisibleLight {
    let mut v = ShadowVisitor {
        triangles,
        frame: beam.frame,
        pieces: vec![LitPiece::new(beam.section)],
        misses: Vec::new(),
        lo: Vec2::ZERO,
        hi: Vec2::ZERO,
        planes: [(Vec3::ZERO, 0.0); 6],
        stats: BeamStats::default(),
    };
    v.update_bounds();
    bvh.traverse(&mut v);
    *stats += v.stats;
    VisibleLight { frame: beam.frame, pieces: v.pieces.iter().map(|p| p.section).collect(), light_area: beam.area() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_bvh::BuildOptions;

    #[test]
    fn square_occluder_parallel_to_square_light() {
        // Light: unit square at z = 2; occluder: square of half-width 0.25 at z = 1 centred above
        // the origin. From the origin the occluder's shadow on the light plane is a square of
        // half-width 0.5: exactly the whole light (side 1, centred) → visible 0 when centred.
        let light = [
            Vec3::new(-0.5, -0.5, 2.0),
            Vec3::new(0.5, -0.5, 2.0),
            Vec3::new(0.5, 0.5, 2.0),
            Vec3::new(-0.5, 0.5, 2.0),
        ];
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
        // Shifted sideways by x: the shadow moves by −x·(2−1)/1 = −x on the light plane.
        let v = visible_light(&bvh, &occ, Vec3::new(0.1, 0.0, 0.0), &light, -Vec3::Z, &mut stats).unwrap();
        assert!((v.fraction() - 0.75).abs() < 1e-5);
        let v = visible_light(&bvh, &occ, Vec3::new(0.6, 0.0, 0.0), &light, -Vec3::Z, &mut stats).unwrap();
        // Shadow x-range: [−0.6 − 0.25 + ..]: centre at 2·0.6 − 0.6 ... computed: centre c = 0.6 − 2·0.6 = −0.6,
        // so the shadow covers x ∈ [−0.85, −0.35] ∩ [−0.5, 0.5] = [−0.5, −0.35]: area 0.15 × 0.5.
        assert!((v.fraction() - (1.0 - 0.15 * 0.5)).abs() < 1e-4, "{}", v.fraction());
        assert!(stats.bvh_steps > 0 && stats.intersections > 0);
    }
}
