//! Exact primary visibility (001 §3): the eye beam through a region of the image traverses the BVH
//! front to back as a list of pieces, each owned by the nearest triangle seen through it, split at
//! triangle edges. Where a triangle overlaps a piece already owned by another, the piece is split
//! along the line where the two planes are at equal depth: the inverse ray parameter `1/s` of a
//! plane is an affine function of the image-plane point, so that line is straight. A piece visits
//! only nodes that may be in front of what it sees ([`node_view`]), and the triangles that a grid
//! of rays sees split the beam first ([`seeds`]), so hidden geometry costs little. After each
//! triangle, the pieces it split that see the same thing and share a whole edge are joined again
//! where their union is convex ([`merge`]): the mesh's neighbouring triangles otherwise leave the
//! beam cut along every extended edge (Sponza: 7.7 pieces per visible triangle without, 1.6 with).

use super::coverage::PixelGrid;
use super::eye_budget::eye_trace_seconds;
use super::shadow_beam::BeamStats;
use beam_bvh::FlatBvh;
use beam_math::Triangle;
use beam_math::glam::{DVec3, Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, KEEP_CORNERS, Part, ProjectedTriangle, Section, merge, split_section};
use node_view::NodeView;
use piece::InverseDepth;
pub use piece::{NEAR, Piece};
pub(crate) use seeds::nearest_first;
use seeds::seen_by_rays;

mod node_view;
mod piece;
mod seeds;

/// The fuzzy side tests of a split (001 App. A), as a fraction of the piece's size: corners this
/// close to a triangle edge count as on it, so the mesh's shared vertices do not cut slivers far
/// below a pixel (1e-6 left half the pieces of Sponza under 1e-9 of the image, and cost 2×).
const SPLIT_EPS: f32 = 1e-5;

/// Corners of two pieces this close (as a fraction of their size, beyond the rounding of their
/// coordinates) are the same corner when pieces are joined: a shared edge cut from both sides
/// differs only by rounding, and a larger tolerance moves outlines enough to show in the coverage
/// (1e-5 left pixels of the conference room 1.6e-3 off a coverage sum of one).
const JOIN_EPS: f32 = 1e-8;

/// Pieces smaller than this fraction of the window are final: they are not split again, and
/// whatever they see first keeps them. Triangles far below a pixel that cross one another (chair
/// feet at the far end of the conference room) otherwise cut the beam into their whole
/// arrangement, tens of thousands of pieces of 1e-8 of a pixel. A final piece's pixel is off by at
/// most its area, 1e-11 of the window: under 1e-6 of a pixel for regions of up to 256² pixels.
const FINAL_AREA: f32 = 1e-11;

/// The eye beam of one image region traced through the BVH as a list of pieces (001 §3.3–3.4).
/// Each node is visited with the pieces that may see into it, nearest child first; a leaf's
/// triangles split those pieces, and the parts carry on from there to the nodes left (sub-beams
/// continue where they were made). A piece stops visiting nodes wholly behind its own surface, so
/// hidden geometry costs one node test per piece that covers it.
struct EyeTracer<'a> {
    frame: BeamFrame,
    bvh: &'a FlatBvh,
    triangles: &'a [Triangle],
    pieces: Vec<Piece>,
    /// The piece lists of the nodes on the current path, one after another.
    lists: Vec<u32>,
    /// Pieces being split by a leaf's triangles (scratch).
    work: Vec<u32>,
    /// What one piece becomes after a split (scratch).
    out: Vec<Piece>,
    /// Hit parts of the piece being split (scratch).
    hits: Vec<Section>,
    /// Pieces a triangle split, and their parts (scratch).
    touched: Vec<u32>,
    lo: Vec2,
    hi: Vec2,
    /// `(apex − origin)·u` and `·v`: image coordinates of the ray along the view axis.
    offset: Vec2,
    /// Pieces smaller than this are final ([`FINAL_AREA`] of the window).
    min_area: f32,
    /// Pieces tested against triangles so far (for the budget).
    checks: u64,
    /// Predicted thread-seconds the trace may take ([`eye_trace_seconds`]); past them it stops.
    budget: f64,
    /// True once the budget is spent: the pieces are incomplete.
    over: bool,
    stats: BeamStats,
}

impl EyeTracer<'_> {
    /// Visit node `i` with the pieces `self.lists[list]`.
    fn visit(&mut self, i: usize, list: core::ops::Range<usize>) {
        if self.over {
            return;
        }
        let node = self.bvh.nodes[i];
        if node.is_leaf() {
            let first = node.right_or_first as usize;
            let bvh = self.bvh;
            self.leaf(&bvh.prims[first..first + node.count as usize], list);
            return;
        }
        let before = self.pieces.len();
        let children = [i + 1, node.right_or_first as usize];
        let views = children.map(|c| NodeView::of(&self.frame, self.offset, (self.lo, self.hi), &self.bvh.nodes[c]));
        self.stats.bvh_steps += 2;
        let order = match (&views[0], &views[1]) {
            (Some(a), Some(b)) if b.near < a.near => [1, 0],
            _ => [0, 1],
        };
        for k in order {
            let Some(view) = &views[k] else { continue };
            let start = self.lists.len();
            // The node's own pieces, and the parts they were split into by the nodes visited since.
            for j in list.clone() {
                let p = self.lists[j];
                if self.open(&self.pieces[p as usize]) && view.meets(&self.pieces[p as usize]) {
                    self.lists.push(p);
                }
            }
            for p in before..self.pieces.len() {
                if self.open(&self.pieces[p]) && view.meets(&self.pieces[p]) {
                    self.lists.push(p as u32);
                }
            }
            if self.lists.len() > start {
                self.visit(children[k], start..self.lists.len());
            }
            self.lists.truncate(start);
        }
    }

    /// True when `piece` may still be split: not final ([`FINAL_AREA`]).
    fn open(&self, piece: &Piece) -> bool {
        piece.area >= self.min_area
    }

    /// Split the pieces `self.lists[list]` by the triangles `prims`.
    fn leaf(&mut self, prims: &[u32], list: core::ops::Range<usize>) {
        let mut work = core::mem::take(&mut self.work);
        work.clear();
        work.extend_from_slice(&self.lists[list]);
        for &p in prims {
            self.stats.triangle_tests += 1;
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
            // Parts made by this triangle are not split by it again.
            let mut touched = core::mem::take(&mut self.touched);
            touched.clear();
            self.checks += work.len() as u64;
            for w in 0..work.len() {
                let first_new = self.pieces.len();
                if self.split_piece(work[w] as usize, p, &projected, depth) {
                    touched.push(work[w]);
                    touched.extend(first_new as u32..self.pieces.len() as u32);
                }
                work.extend(first_new as u32..self.pieces.len() as u32);
            }
            self.join(&touched);
            self.touched = touched;
            if eye_trace_seconds(&self.stats, self.checks) > self.budget {
                self.over = true;
                break;
            }
        }
        self.work = work;
    }

    /// Join the pieces `touched` that see the same triangle (or both the background) and share
    /// a whole edge, while their union is convex: the first keeps the union, the other is gone.
    fn join(&mut self, touched: &[u32]) {
        for a in 0..touched.len() {
            let ia = touched[a] as usize;
            let mut b = a + 1;
            while b < touched.len() && !self.pieces[ia].is_gone() {
                let ib = touched[b] as usize;
                let (pa, pb) = (&self.pieces[ia], &self.pieces[ib]);
                b += 1;
                if pb.is_gone() || pa.prim != pb.prim {
                    continue;
                }
                let (lo, hi) = (pa.lo.min(pb.lo), pa.hi.max(pb.hi));
                let tol =
                    JOIN_EPS * (hi - lo).max_element() + 4.0 * f32::EPSILON * lo.abs().max(hi.abs()).max_element();
                let apart = (pa.lo - pb.hi).max(pb.lo - pa.hi).max_element();
                if apart > tol {
                    continue;
                }
                if let Some(section) = merge(&pa.section, &pb.section, tol, KEEP_CORNERS) {
                    self.pieces[ia] = pa.with_section(section);
                    self.pieces[ib] = Piece::gone();
                    self.stats.joins += 1;
                    b = a + 1;
                }
            }
        }
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
        let (min, max) = new.nearer(&old_depth, &depth);
        if min >= 0.0 && max > 0.0 {
            self.out.push(new);
        } else if max <= 0.0 || g.k.length_squared() == 0.0 {
            self.out.push(Piece::new(section, Some(old_prim), Some(old_depth)));
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
                Err(_) => self.out.push(Piece::new(section, Some(old_prim), Some(old_depth))),
            }
        }
    }

    /// Split piece `i` by the triangle `prim` (projected, inverse depth `depth`) where the triangle
    /// is in front of what the piece sees: the piece is replaced by its miss parts (same owner) and
    /// its resolved hit parts, the first in place and the others appended. False when the triangle
    /// hides none of it (nothing changed).
    fn split_piece(&mut self, i: usize, prim: u32, projected: &ProjectedTriangle, depth: InverseDepth) -> bool {
        // The piece is read in place, never copied: most pieces of a node's list miss a given
        // triangle or lie in front of it.
        let piece = &self.pieces[i];
        if !self.open(piece) || !projected.overlaps(piece.lo, piece.hi) {
            return false;
        }
        // Where the triangle's plane is behind the owner's it must not split the piece: hidden at
        // every corner of the piece means hidden on all of it (both inverse depths are affine);
        // partly hidden, only the triangle's part in front (g > 0) splits it, so hidden edges never
        // fragment the piece.
        let mut front = None;
        if let Some(owner) = piece.depth {
            let g = depth.minus(&owner);
            let (min, max) = piece.nearer(&owner, &depth);
            if max <= 0.0 {
                return false;
            }
            if min < 0.0 && g.k.length_squared() > 0.0 {
                let a = -g.k0 * g.k / g.k.length_squared();
                match projected.clip(a, -g.k) {
                    Some(p) if p.overlaps(piece.lo, piece.hi) => front = Some(p),
                    // The triangle lies behind where its plane is in front.
                    _ => return false,
                }
            }
        }
        self.stats.intersections += 1;
        let (out, hits) = (&mut self.out, &mut self.hits);
        out.clear();
        hits.clear();
        let emitted =
            split_section(&piece.section, front.as_ref().unwrap_or(projected), SPLIT_EPS, &mut |part, s| match part {
                Part::Hit => hits.push(s),
                Part::Miss => out.push(piece.with_section(s)),
            });
        if emitted.is_err() || self.hits.is_empty() {
            return false;
        }
        let owner = piece.prim.zip(piece.depth);
        self.stats.hit_beams += self.hits.len() as u64;
        for k in 0..self.hits.len() {
            self.resolve(self.hits[k], owner, prim, depth);
        }
        // A hit part always survives resolution, so `out` is never empty here.
        self.pieces[i] = self.out[0];
        self.pieces.extend_from_slice(&self.out[1..]);
        true
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
    visible_surface_within(bvh, triangles, frame, (lo, hi), None, f64::INFINITY, stats).unwrap_or_default()
}

/// [`visible_surface`] through `window`, or `None` once its trace is predicted to have taken more
/// than `budget` thread-seconds ([`eye_trace_seconds`]; the work done so far is in `stats`).
/// `seeds`: the triangles a grid of rays through the window sees, nearest first, where the caller
/// has cast it ([`nearest_first`]); else the beam casts its own.
pub(crate) fn visible_surface_within(
    bvh: &FlatBvh,
    triangles: &[Triangle],
    frame: &BeamFrame,
    (lo, hi): (Vec2, Vec2),
    seeds: Option<&[u32]>,
    budget: f64,
    stats: &mut BeamStats,
) -> Option<Vec<Piece>> {
    let rect = [Vec2::new(lo.x, lo.y), Vec2::new(hi.x, lo.y), Vec2::new(hi.x, hi.y), Vec2::new(lo.x, hi.y)];
    let Ok(section) = Section::from_slice(&rect) else { return Some(Vec::new()) };
    let r = frame.apex - frame.origin;
    let mut t = EyeTracer {
        frame: *frame,
        bvh,
        triangles,
        pieces: vec![Piece::new(section, None, None)],
        lists: vec![0],
        work: Vec::new(),
        out: Vec::new(),
        hits: Vec::new(),
        touched: Vec::new(),
        lo,
        hi,
        offset: Vec2::new(r.dot(frame.u), r.dot(frame.v)),
        min_area: FINAL_AREA * (hi - lo).x * (hi - lo).y,
        checks: 0,
        budget,
        over: false,
        stats: BeamStats::default(),
    };
    if bvh.nodes.first().is_some_and(|root| NodeView::of(frame, t.offset, (lo, hi), root).is_some()) {
        // The triangles a grid of rays sees split the beam first: the big near ones then own most
        // of it, and nodes behind them are culled, whatever order their boxes come in.
        match seeds {
            Some(seeds) => t.leaf(seeds, 0..1),
            None => t.leaf(&seen_by_rays(bvh, triangles, frame, lo, hi), 0..1),
        };
        t.lists = (0..t.pieces.len() as u32).collect();
        t.stats.bvh_steps += 1;
        t.visit(0, 0..t.lists.len());
    }
    *stats += t.stats;
    if t.over {
        return None;
    }
    t.pieces.retain(|p| !p.is_gone());
    Some(t.pieces)
}

/// The point of `prim`'s plane seen through image-plane point `c`.
#[must_use]
pub fn point_on_piece(frame: &BeamFrame, piece: &Piece, c: Vec2) -> Option<Vec3> {
    let inv = piece.depth?.at(c);
    (inv > 0.0).then(|| frame.apex + (frame.point(c) - frame.apex) / inv)
}

/// A triangle's plane seen from a beam frame's apex through the pixels of an image, in double
/// precision: the view ray through pixel point `m` runs along `d(m) = d0 + m.x·du + m.y·dv` from
/// the apex ([`PixelGrid::view_rays`]), and meets the plane (normal `n`, not unit) at
/// `apex + h / (n·d(m)) · d(m)`, `h` the apex's height over it times `|n|`; set up once for the
/// points of a piece.
pub(crate) struct TrianglePlane {
    apex: DVec3,
    rays: [DVec3; 3],
    /// `n·d0`, `n·du`, `n·dv`.
    n_rays: [f64; 3],
    height: f64,
}

impl TrianglePlane {
    pub(crate) fn new(frame: &BeamFrame, grid: PixelGrid, tri: &Triangle) -> Self {
        let apex = frame.apex.as_dvec3();
        let [a, b, e] = tri.v.map(|v| v.as_dvec3());
        let n = (b - a).cross(e - a);
        let rays = grid.view_rays(frame);
        Self { apex, rays, n_rays: rays.map(|d| n.dot(d)), height: (a - apex).dot(n) }
    }

    /// The point of the plane seen through pixel point `m` (pixel `(x, y)` is the unit square at
    /// `(x, y)`): where the view ray meets the plane, in double precision; `None` along the plane
    /// or behind the apex. Where a piece's inverse depth ([`point_on_piece`]) is read from far
    /// away, its f32 plane puts the point up to about 1e-4 of the scene's size off the surface,
    /// behind it as often as in front, and a shade point offset from there by the shading
    /// tolerance can lie behind its own triangle.
    #[must_use]
    pub(crate) fn point(&self, m: Vec2) -> Option<Vec3> {
        let (x, y) = (f64::from(m.x), f64::from(m.y));
        let [d0, du, dv] = self.rays;
        let [n0, nu, nv] = self.n_rays;
        let t = self.height / (n0 + x * nu + y * nv);
        (t.is_finite() && t > 0.0).then(|| (self.apex + t * (d0 + x * du + y * dv)).as_vec3())
    }
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

    /// A trace stops at its budget and says so; without one it gives [`visible_surface`]'s pieces.
    #[test]
    fn a_trace_past_its_budget_gives_no_pieces() {
        let frame = BeamFrame::new(Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::X).unwrap();
        let tris: Vec<Triangle> = (0..40)
            .map(|i| {
                let (x, z) = (-1.0 + 0.05 * i as f32, 2.0 + 0.01 * i as f32);
                Triangle::new(Vec3::new(x, -1.0, z), Vec3::new(x + 0.3, -1.0, z), Vec3::new(x, 1.0, z))
            })
            .collect();
        let bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        let window = (Vec2::splat(-1.0), Vec2::splat(1.0));
        let mut stats = BeamStats::default();
        let all = visible_surface_within(&bvh, &tris, &frame, window, None, f64::INFINITY, &mut stats).unwrap();
        let whole = visible_surface(&bvh, &tris, &frame, window.0, window.1, &mut BeamStats::default());
        assert_eq!(all.len(), whole.len());
        assert!(all.iter().zip(&whole).all(|(a, b)| a.prim == b.prim && a.section == b.section));
        let cost = eye_trace_seconds(&stats, 0);
        let mut cut = BeamStats::default();
        assert!(visible_surface_within(&bvh, &tris, &frame, window, None, 0.5 * cost, &mut cut).is_none());
        assert!(cut.triangle_tests > 0 && cut.triangle_tests <= stats.triangle_tests);
    }
}
