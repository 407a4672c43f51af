//! Exact primary visibility (001 §3): a beam from the eye through an image tile traverses the BVH
//! front to back and is split at triangle edges into pieces, each owned by the nearest triangle seen
//! through it. Where a triangle overlaps a piece already owned by another, the piece is split along
//! the line where the two planes are at equal depth: the inverse ray parameter `1/s` of a plane is an
//! affine function of the image-plane point, so that line is straight. Hit pieces stay in the beam
//! until every node left is farther than all of them (001 Fig. 4d).

use super::shadow_beam::BeamStats;
use beam_bvh::{Control, FlatBvh, NodeVisitor};
use beam_math::collide::aabb_outside_planes;
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, Part, ProjectedTriangle, Section, split_section};
use beam_math::{Aabb, Triangle};

/// Near clipping depth of the eye beam, in units of the image-plane distance.
pub const NEAR: f32 = 1e-4;

/// `1/s` of a plane as an affine function `k0 + k·c` of the image-plane point `c` (larger = nearer).
#[derive(Clone, Copy, Debug, PartialEq)]
struct InverseDepth {
    k0: f32,
    k: Vec2,
}

impl InverseDepth {
    /// For the plane through `tri`; `None` when the plane passes through the apex (seen edge-on).
    fn of(frame: &BeamFrame, tri: &Triangle) -> Option<Self> {
        let n = tri.scaled_normal();
        let h = n.dot(frame.apex - tri.v[0]);
        if h.abs() <= 1e-12 * n.length() * (frame.apex - tri.v[0]).length() {
            return None;
        }
        // s(c) = −h / (n·w(c)) with w(c) = origin − apex + c.x·u + c.y·v.
        let k0 = -n.dot(frame.origin - frame.apex) / h;
        Some(Self { k0, k: Vec2::new(-n.dot(frame.u), -n.dot(frame.v)) / h })
    }

    fn at(&self, c: Vec2) -> f32 {
        self.k0 + self.k.dot(c)
    }

    fn minus(&self, o: &Self) -> Self {
        Self { k0: self.k0 - o.k0, k: self.k - o.k }
    }
}

/// A piece of the eye beam and the triangle it sees (none: the background).
#[derive(Clone, Copy, Debug)]
pub struct Piece {
    /// Cross-section on the image plane.
    pub section: Section,
    /// The visible triangle.
    pub prim: Option<u32>,
    depth: Option<InverseDepth>,
}

struct EyeVisitor<'a> {
    frame: BeamFrame,
    triangles: &'a [Triangle],
    pieces: Vec<Piece>,
    next: Vec<Piece>,
    /// Hit parts of the piece being split (scratch).
    hits: Vec<Section>,
    planes: [(Vec3, f32); 5],
    lo: Vec2,
    hi: Vec2,
    stats: BeamStats,
}

impl EyeVisitor<'_> {
    /// Largest forward depth seen through any piece, or infinity while a piece sees background.
    fn farthest(&self) -> f32 {
        let mut far = 0.0f32;
        for p in &self.pieces {
            let Some(d) = p.depth else { return f32::INFINITY };
            for &c in p.section.vertices() {
                let inv = d.at(c);
                if !(inv > 0.0) {
                    return f32::INFINITY;
                }
                far = far.max(self.frame.distance / inv);
            }
        }
        far
    }

    /// Resolve a piece seen through both its current owner and `tri` (inverse depth `depth`).
    fn resolve(&mut self, section: Section, old: Option<(u32, InverseDepth)>, prim: u32, depth: InverseDepth) {
        let new = Piece { section, prim: Some(prim), depth: Some(depth) };
        let Some((old_prim, old_depth)) = old else {
            self.next.push(new);
            return;
        };
        let keep = Piece { section, prim: Some(old_prim), depth: Some(old_depth) };
        let g = depth.minus(&old_depth);
        let values: Vec<f32> = section.vertices().iter().map(|&c| g.at(c)).collect();
        let scale = values.iter().fold(0.0f32, |m, v| m.max(v.abs())).max(1e-30);
        if values.iter().all(|&v| v >= -1e-6 * scale) && values.iter().any(|&v| v > 1e-6 * scale) {
            self.next.push(new);
        } else if values.iter().all(|&v| v <= 1e-6 * scale) || g.k.length_squared() == 0.0 {
            self.next.push(keep);
        } else {
            // Split along g(c) = 0: the new triangle is nearer where g > 0.
            let a = -g.k0 * g.k / g.k.length_squared();
            match section.split(a, -g.k, 0.0) {
                Ok((near, far)) => {
                    if !near.is_empty() {
                        self.next.push(Piece { section: near, ..new });
                    }
                    if !far.is_empty() {
                        self.next.push(Piece { section: far, ..keep });
                    }
                }
                Err(_) => self.next.push(keep),
            }
        }
    }
}

impl NodeVisitor for EyeVisitor<'_> {
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        self.stats.bvh_steps += 1;
        if aabb_outside_planes(bounds, &self.planes) {
            return None;
        }
        // Entry distance: the box's smallest forward depth.
        let f = self.frame.normal;
        let nearest = Vec3::select(f.cmpgt(Vec3::ZERO), bounds.min, bounds.max);
        Some(f.dot(nearest - self.frame.apex).max(0.0))
    }

    fn cutoff(&self) -> f32 {
        self.farthest()
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        for &p in prims {
            let tri = &self.triangles[p as usize];
            let Some(projected) =
                ProjectedTriangle::new_in_window(&self.frame, tri, NEAR, f32::INFINITY, self.lo, self.hi)
            else {
                continue;
            };
            if !projected.overlaps(self.lo, self.hi) {
                continue;
            }
            let Some(depth) = InverseDepth::of(&self.frame, tri) else { continue };
            self.next.clear();
            let pieces = core::mem::take(&mut self.pieces);
            for piece in &pieces {
                // Hidden: the triangle's plane is behind the owner's at every corner of the piece,
                // hence (both inverse depths being affine) on all of it; it must not split the piece.
                if let Some(owner) = piece.depth {
                    let g = depth.minus(&owner);
                    if piece.section.vertices().iter().all(|&c| g.at(c) <= 0.0) {
                        self.next.push(*piece);
                        continue;
                    }
                }
                self.stats.intersections += 1;
                let (start, next, hits) = (self.next.len(), &mut self.next, &mut self.hits);
                hits.clear();
                let emitted = split_section(&piece.section, &projected, 1e-6, &mut |part, s| match part {
                    Part::Hit => hits.push(s),
                    Part::Miss => next.push(Piece { section: s, ..*piece }),
                });
                if emitted.is_err() {
                    self.next.truncate(start);
                    self.next.push(*piece);
                    continue;
                }
                self.stats.hit_beams += self.hits.len() as u64;
                for i in 0..self.hits.len() {
                    self.resolve(self.hits[i], piece.prim.zip(piece.depth), p, depth);
                }
            }
            self.pieces = core::mem::take(&mut self.next);
        }
        Control::Continue
    }
}

/// The exact visible surface through the rectangle `[lo, hi]` of the image plane of `frame`: pieces
/// covering the rectangle, each with the triangle it sees.
pub fn visible_surface(
    bvh: &FlatBvh,
    triangles: &[Triangle],
    frame: &BeamFrame,
    lo: Vec2,
    hi: Vec2,
    stats: &mut BeamStats,
) -> Vec<Piece> {
    let rect = [Vec2::new(lo.x, lo.y), Vec2::new(hi.x, lo.y), Vec2::new(hi.x, hi.y), Vec2::new(lo.x, hi.y)];
    let Ok(section) = Section::from_slice(&rect) else { return Vec::new() };
    let apex = frame.apex;
    let corners = rect.map(|q| frame.point(q) - apex);
    let mid = frame.point(0.5 * (lo + hi)) - apex;
    let mut planes = [(Vec3::ZERO, 0.0); 5];
    for i in 0..4 {
        let mut n = corners[i].cross(corners[(i + 1) % 4]);
        if n.dot(mid) > 0.0 {
            n = -n;
        }
        planes[i] = (n, n.dot(apex));
    }
    let f = frame.normal / frame.distance;
    planes[4] = (-f, -f.dot(apex) - NEAR);
    let mut v = EyeVisitor {
        frame: *frame,
        triangles,
        pieces: vec![Piece { section, prim: None, depth: None }],
        next: Vec::new(),
        hits: Vec::new(),
        planes,
        lo,
        hi,
        stats: BeamStats::default(),
    };
    bvh.traverse(&mut v);
    *stats += v.stats;
    v.pieces
}

/// The point of `prim`'s plane seen through image-plane point `c`.
#[must_use]
pub fn point_on_piece(frame: &BeamFrame, piece: &Piece, c: Vec2) -> Option<Vec3> {
    let inv = piece.depth?.at(c);
    (inv > 0.0).then(|| frame.apex + (frame.point(c) - frame.apex) / inv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_bvh::BuildOptions;

    #[test]
    fn nearer_triangle_wins_and_crossing_triangles_split_at_their_intersection() {
        let frame = BeamFrame::new(Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::X).unwrap();
        // A far big square at z = 4 and a near small one at z = 2 covering the right half of the view.
        let q = |z: f32, x0: f32, x1: f32| {
            [
                Triangle::new(Vec3::new(x0, -10.0, z), Vec3::new(x1, -10.0, z), Vec3::new(x1, 10.0, z)),
                Triangle::new(Vec3::new(x0, -10.0, z), Vec3::new(x1, 10.0, z), Vec3::new(x0, 10.0, z)),
            ]
        };
        let mut tris = q(4.0, -10.0, 10.0).to_vec();
        tris.extend(q(2.0, 0.0, 10.0));
        let bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        let mut stats = BeamStats::default();
        let pieces = visible_surface(&bvh, &tris, &frame, Vec2::splat(-1.0), Vec2::splat(1.0), &mut stats);
        let area = |pred: &dyn Fn(u32) -> bool| {
            pieces.iter().filter(|p| p.prim.is_some_and(pred)).map(|p| p.section.area()).sum::<f32>()
        };
        assert!((area(&|p| p >= 2) - 2.0).abs() < 1e-4, "near half: {}", area(&|p| p >= 2));
        assert!((area(&|p| p < 2) - 2.0).abs() < 1e-4);
        assert!(pieces.iter().all(|p| p.prim.is_some()));
        // A tilted plane crossing z = 3 at x = 0: x < 0 is nearer (z = 3 + x·0.5 < 3).
        let tilt = vec![
            Triangle::new(Vec3::new(-10.0, -10.0, -2.0), Vec3::new(10.0, -10.0, 8.0), Vec3::new(10.0, 10.0, 8.0)),
            Triangle::new(Vec3::new(-10.0, -10.0, -2.0), Vec3::new(10.0, 10.0, 8.0), Vec3::new(-10.0, 10.0, -2.0)),
        ];
        let mut both = tilt.clone();
        both.extend(q(3.0, -10.0, 10.0));
        let bvh = FlatBvh::build(&both, &BuildOptions::sah());
        let pieces = visible_surface(&bvh, &both, &frame, Vec2::splat(-1.0), Vec2::splat(1.0), &mut stats);
        let tilted: f32 = pieces.iter().filter(|p| p.prim.is_some_and(|x| x < 2)).map(|p| p.section.area()).sum();
        // The planes meet where 3 + 0.5·x = 3 → x = 0 on the z = 3 plane, i.e. image x = 0.
        assert!((tilted - 2.0).abs() < 1e-3, "{tilted}");
    }
}
