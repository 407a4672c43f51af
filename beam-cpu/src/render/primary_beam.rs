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
    /// Bounding rectangle of the section.
    lo: Vec2,
    hi: Vec2,
}

impl Piece {
    fn new(section: Section, prim: Option<u32>, depth: Option<InverseDepth>) -> Self {
        let (lo, hi) = section.bounds();
        Self { section, prim, depth, lo, hi }
    }

    /// Another cross-section seeing the same triangle at the same depths.
    #[must_use]
    pub fn with_section(&self, section: Section) -> Self {
        Self::new(section, self.prim, self.depth)
    }
}

struct EyeVisitor<'a> {
    frame: BeamFrame,
    triangles: &'a [Triangle],
    pieces: Vec<Piece>,
    /// What one piece becomes after a split (scratch).
    out: Vec<Piece>,
    /// Hit parts of the piece being split (scratch).
    hits: Vec<Section>,
    planes: [(Vec3, f32); 5],
    lo: Vec2,
    hi: Vec2,
    /// Largest forward depth seen through any piece (infinity while one sees background).
    far: f32,
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

    /// Resolve a piece seen through both its current owner and `tri` (inverse depth `depth`) into
    /// `self.out`.
    fn resolve(&mut self, section: Section, old: Option<(u32, InverseDepth)>, prim: u32, depth: InverseDepth) {
        let new = Piece::new(section, Some(prim), Some(depth));
        let Some((old_prim, old_depth)) = old else {
            self.out.push(new);
            return;
        };
        let g = depth.minus(&old_depth);
        let (min, max) = section
            .vertices()
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &c| (lo.min(g.at(c)), hi.max(g.at(c))));
        let tol = 1e-6 * min.abs().max(max.abs()).max(1e-30);
        if min >= -tol && max > tol {
            self.out.push(new);
        } else if max <= tol || g.k.length_squared() == 0.0 {
            self.out.push(Piece { prim: Some(old_prim), depth: Some(old_depth), ..new });
        } else {
            // Split along g(c) = 0: the new triangle is nearer where g > 0.
            let a = -g.k0 * g.k / g.k.length_squared();
            match section.split(a, -g.k, 0.0) {
                Ok((near, far)) => {
                    if !near.is_empty() {
                        self.out.push(Piece::new(near, Some(prim), Some(depth)));
                    }
                    if !far.is_empty() {
                        self.out.push(Piece::new(far, Some(old_prim), Some(old_depth)));
                    }
                }
                Err(_) => self.out.push(Piece { prim: Some(old_prim), depth: Some(old_depth), ..new }),
            }
        }
    }

    /// Split every piece the triangle `prim` (projected, inverse depth `depth`) overlaps and is not
    /// hidden behind, in place: a piece is replaced by its miss parts (same owner) and its resolved
    /// hit parts. True when any piece changed.
    fn split_pieces(&mut self, prim: u32, projected: &ProjectedTriangle, depth: InverseDepth) -> bool {
        let mut changed = false;
        // Pieces [0, end) are the ones from before this triangle; new parts are appended.
        let end = self.pieces.len();
        for i in 0..end {
            let piece = &self.pieces[i];
            if !projected.overlaps(piece.lo, piece.hi) {
                continue;
            }
            // Where the triangle's plane is behind the owner's it must not split the piece: hidden
            // at every corner of the piece means hidden on all of it (both inverse depths are affine);
            // partly hidden, only the triangle's part in front (g > 0) splits it, so hidden edges
            // never fragment the piece.
            let mut front = None;
            if let Some(owner) = piece.depth {
                let g = depth.minus(&owner);
                let (min, max) = piece
                    .section
                    .vertices()
                    .iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &c| (lo.min(g.at(c)), hi.max(g.at(c))));
                if max <= 0.0 {
                    continue;
                }
                if min < 0.0 && g.k.length_squared() > 0.0 {
                    let a = -g.k0 * g.k / g.k.length_squared();
                    match projected.clip(a, -g.k) {
                        Some(p) if p.overlaps(piece.lo, piece.hi) => front = Some(p),
                        Some(_) => continue,
                        // Nothing in front, or no capacity left: split by the whole triangle below.
                        None => {}
                    }
                }
            }
            let piece = *piece;
            self.stats.intersections += 1;
            let (out, hits) = (&mut self.out, &mut self.hits);
            out.clear();
            hits.clear();
            let emitted =
                split_section(&piece.section, front.as_ref().unwrap_or(projected), 1e-6, &mut |part, s| match part {
                    Part::Hit => hits.push(s),
                    Part::Miss => out.push(piece.with_section(s)),
                });
            if emitted.is_err() || self.hits.is_empty() {
                continue;
            }
            changed = true;
            self.stats.hit_beams += self.hits.len() as u64;
            for k in 0..self.hits.len() {
                self.resolve(self.hits[k], piece.prim.zip(piece.depth), prim, depth);
            }
            // A hit part always survives resolution, so `out` is never empty here.
            self.pieces[i] = self.out[0];
            self.pieces.extend_from_slice(&self.out[1..]);
        }
        changed
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
        self.far
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        let mut changed = false;
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
            changed |= self.split_pieces(p, &projected, depth);
        }
        if changed {
            self.far = self.farthest();
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
    let mut planes = [(Vec3::ZERO, 0.0); 5];
    for (plane, n) in planes.iter_mut().zip(frame.side_normals(lo, hi)) {
        *plane = (n, n.dot(apex));
    }
    let f = frame.normal / frame.distance;
    planes[4] = (-f, -f.dot(apex) - NEAR);
    let mut v = EyeVisitor {
        frame: *frame,
        triangles,
        pieces: vec![Piece::new(section, None, None)],
        out: Vec::new(),
        hits: Vec::new(),
        planes,
        lo,
        hi,
        far: f32::INFINITY,
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
