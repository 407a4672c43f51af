//! Exact visibility of a polygonal light from a point (001 §5): a beam from the shade point to the
//! light polygon meets the triangles of the BVH (or of a shaft's candidate list, [`super::shaft`]);
//! each remaining piece of the light is split exactly at the triangle's edges (001 §3.2); the miss
//! pieces are the visible part of the light.
//!
//! The fast core of 001 §3.4: each triangle is projected once per query (three divides, no
//! clipping unless it reaches behind the point or past the light) into its 2D edge lines, and the
//! pieces, at most four corners each ([`Quad`]), are classified against a line with one 4-lane
//! multiply-add. The order of occluders does not matter for visibility (any triangle between the
//! point and the light blocks), so hit pieces are dropped at once. A BVH references each triangle
//! from exactly one leaf, so the kd-tree mailboxing of 001 §3.4 has nothing to remove here.

use super::packet::Survivor;
use beam_math::Triangle;
use beam_math::glam::{Vec2, Vec3, Vec4};
use beam_math::polybeam::{BeamFrame, Cover, EdgeLines, PolyBeam, Quad};
use beam_render::tolerance::DEPTH_EPS;

mod candidates;
mod depth;
mod silhouette;
mod stats;
pub(crate) mod visible;
pub(crate) mod walk;
mod winding_scratch;

use depth::{CONTACT, clip_depth, cone_meets};
pub use stats::BeamStats;
pub(crate) use winding_scratch::WindingScratch;

/// Fuzzy tolerance of the side tests, as a fraction of the light's size (001 App. A).
const SIDE_EPS: f32 = 1e-6;

/// Buffers a thread reuses from one shadow beam to the next (no allocation per shade point).
#[derive(Default)]
pub(crate) struct ShadowScratch {
    pieces: Vec<Quad>,
    /// Each piece's bounding rectangle as `(lo.x, lo.y, −hi.x, −hi.y)` (see [`ShadowBeam::rect`]).
    boxes: Vec<Vec4>,
    /// The candidates that survived the packet test.
    survivors: Vec<Survivor>,
    /// Their order: sort key (a non-negative `f32`'s bits) above, complemented index below.
    order: Vec<u64>,
    /// The occluders that hit the last beam traced through candidates, when it ended dark
    /// (tested first next time).
    hot: Vec<u32>,
}

/// A shadow beam being traced: its frame, its remaining (lit) pieces and their bounding rectangle.
pub(crate) struct ShadowBeam<'s> {
    pub(crate) frame: BeamFrame,
    /// The apex in the plane's coordinates, `((apex − origin)·u, (apex − origin)·v)`.
    apex_uv: Vec2,
    pieces: &'s mut Vec<Quad>,
    boxes: &'s mut Vec<Vec4>,
    survivors: &'s mut Vec<Survivor>,
    order: &'s mut Vec<u64>,
    hot: &'s mut Vec<u32>,
    lo: Vec2,
    hi: Vec2,
    eps: f32,
    /// Work allowed before the beam stops with its pieces unresolved ([`ShadowBeam::with_budget`]).
    budget: u64,
    /// The depth (a fraction of the light's distance) from which occluders are looked for:
    /// `DEPTH_EPS`, the near plane, unless [`ShadowBeam::with_contact`] asks for less.
    touch: f32,
    /// A triangle crossed the beam before its near plane ([`CONTACT`]).
    contact: bool,
    pub(crate) stats: BeamStats,
}

impl<'s> ShadowBeam<'s> {
    /// The beam of `beam`'s cross-section (cut into pieces of at most four corners).
    pub(crate) fn new(beam: &PolyBeam, scratch: &'s mut ShadowScratch) -> Self {
        let ShadowScratch { pieces, boxes, survivors, order, hot } = scratch;
        pieces.clear();
        let v = beam.section.vertices();
        // A fan of quads around corner 0 (the section is convex and counter-clockwise).
        let mut first = 1;
        while first + 1 < v.len() {
            let last = (first + 2).min(v.len() - 1);
            let corners = if last == first + 2 {
                &[v[0], v[first], v[first + 1], v[last]][..]
            } else {
                &[v[0], v[first], v[last]][..]
            };
            pieces.extend(Quad::new(corners));
            first = last;
        }
        let centroid = beam.section.centroid();
        let scale = v.iter().fold(0.0f32, |m, c| m.max((*c - centroid).length()));
        let f = &beam.frame;
        let r = f.apex - f.origin;
        let mut out = Self {
            frame: *f,
            apex_uv: Vec2::new(r.dot(f.u), r.dot(f.v)),
            pieces,
            boxes,
            survivors,
            order,
            hot,
            lo: Vec2::ZERO,
            hi: Vec2::ZERO,
            eps: SIDE_EPS * scale.max(f32::MIN_POSITIVE),
            budget: u64::MAX,
            touch: DEPTH_EPS,
            contact: false,
            stats: BeamStats::default(),
        };
        out.update_bounds();
        out
    }

    /// This beam, stopping once its work passes `splits` piece splits (a candidate's test counting
    /// 1/32 of one): its remaining pieces are then the lit part and the part not yet resolved.
    pub(crate) fn with_budget(mut self, splits: u64) -> Self {
        self.budget = splits;
        self
    }

    /// True once the work has passed the budget.
    pub(crate) fn over_budget(&self) -> bool {
        self.stats.intersections + self.stats.triangle_tests / 32 > self.budget
    }

    /// This beam, also looking for triangles in contact with its apex: those that cross it between
    /// `CONTACT` of its near plane and the near plane ([`ShadowBeam::in_contact`]).
    pub(crate) fn with_contact(mut self) -> Self {
        self.touch = CONTACT * DEPTH_EPS;
        self
    }

    /// The depth, as a fraction of the light's distance, from which occluders are looked for.
    pub(crate) fn touch(&self) -> f32 {
        self.touch
    }

    /// True when a triangle crossed the beam between the apex and its near plane: what it hides
    /// there is not in the pieces ([`CONTACT`]).
    pub(crate) fn in_contact(&self) -> bool {
        self.contact
    }

    /// True when nothing is left to do: dark, or past the budget.
    pub(crate) fn finished(&self) -> bool {
        self.is_dark() || self.over_budget()
    }

    /// The remaining pieces.
    pub(crate) fn pieces(&self) -> &[Quad] {
        self.pieces
    }

    /// True when nothing of the light is left.
    pub(crate) fn is_dark(&self) -> bool {
        self.pieces.is_empty()
    }

    /// Bounding rectangle of the remaining pieces.
    pub(crate) fn bounds(&self) -> (Vec2, Vec2) {
        (self.lo, self.hi)
    }

    /// A bounding rectangle `[lo, hi]` as `(lo.x, lo.y, −hi.x, −hi.y)`: two such rectangles meet
    /// where `a ≤ (b.hi.x, b.hi.y, −b.lo.x, −b.lo.y)` in all four lanes (one compare), and the
    /// lane-wise minimum of several is their union.
    fn rect(lo: Vec2, hi: Vec2) -> Vec4 {
        Vec4::new(lo.x, lo.y, -hi.x, -hi.y)
    }

    fn update_bounds(&mut self) {
        self.boxes.clear();
        self.boxes.extend(self.pieces.iter().map(|p| {
            let (lo, hi) = p.bounds();
            Self::rect(lo, hi)
        }));
        self.union_boxes();
    }

    fn union_boxes(&mut self) {
        let u = self.boxes.iter().fold(Vec4::INFINITY, |u, b| u.min(*b));
        (self.lo, self.hi) = (Vec2::new(u.x, u.y), Vec2::new(-u.z, -u.w));
    }

    /// Remove from the pieces what `tri` hides: only its part strictly between the apex and the
    /// light counts. True when any piece was hit.
    pub(crate) fn occlude(&mut self, tri: &Triangle) -> bool {
        self.stats.triangle_tests += 1;
        self.occlude_tested(tri, false)
    }

    /// [`ShadowBeam::occlude`] uncounted; `beside_tested`: the planes of [`ShadowBeam::beside`]
    /// were tried on it already (the packet test's `beside_planes`) and are not tried again.
    fn occlude_tested(&mut self, tri: &Triangle, beside_tested: bool) -> bool {
        let f = &self.frame;
        let (near, far) = (DEPTH_EPS * f.distance, (1.0 - DEPTH_EPS) * f.distance);
        let w = tri.v.map(|v| v - f.apex);
        let h = w.map(|w| w.dot(f.normal));
        let touch = self.touch * f.distance;
        if h.iter().all(|&h| h < touch) || h.iter().all(|&h| h > far) || h.iter().any(|h| h.is_nan()) {
            return false;
        }
        if h.iter().all(|&h| h >= near && h <= far) {
            // Wholly in the depth range: project the three corners (001 §3.4).
            let q =
                core::array::from_fn(|i| self.apex_uv + Vec2::new(w[i].dot(f.u), w[i].dot(f.v)) * (f.distance / h[i]));
            return self.occlude_projected(&q);
        }
        if !beside_tested && self.beside(&w) {
            return false;
        }
        if !self.contact && touch < near && h.iter().any(|&h| h < near) {
            // Its part between the contact depth and the near plane, where it meets the pieces.
            let (part, n) = clip_depth(&w, &h, (touch, near));
            let plane = (w[1] - w[0]).cross(w[2] - w[0]);
            self.contact = n >= 3
                && self.pieces.iter().any(|piece| cone_meets(&self.frame, piece, &part[..n], (plane, w[0]), near));
        }
        // Reaching behind the point or past the light: clip to the depth range first. Depth
        // clipping only: shadow beams can graze the light's plane, where planes through the apex and
        // the window are nearly parallel to it and clipping by them is ill-conditioned.
        let (part, n) = clip_depth(&w, &h, (near, far));
        if n < 3 {
            return false;
        }
        let mut q = [Vec2::ZERO; 9];
        let (mut lo, mut hi) = (Vec2::INFINITY, Vec2::NEG_INFINITY);
        for ((w, h), q) in part[..n].iter().zip(&mut q) {
            *q = self.apex_uv + Vec2::new(w.dot(f.u), w.dot(f.v)) * (f.distance / h);
            lo = lo.min(*q);
            hi = hi.max(*q);
        }
        if !self.meets_rect(lo, hi) {
            return false;
        }
        self.split_pieces::<9>(&q[..n], lo, hi)
    }

    /// True when a plane keeps the triangle with corners `w` (relative to the apex) out of the
    /// pyramid from the apex through the pieces' bounding rectangle, with that rectangle more than
    /// the fuzzy tolerance beyond it. Projection from the apex keeps the side of a plane through
    /// the apex, so the triangle's part in front of the apex projects on its side of the line where
    /// the plane through the apex and one of its edges meets the light's plane; and a point at
    /// depth `h` of its plane `m·w = e` projects onto the line `m·(x − apex) = e·d / h`, so its part
    /// before the far plane projects beyond that line at `h = far`. Either way it hides nothing and
    /// touches no piece's cone. A triangle that passes close beside the shade point and reaches
    /// behind it projects into a long sliver whose bounding rectangle covers the light: these four
    /// planes drop it before it is clipped, projected and split.
    fn beside(&self, w: &[Vec3; 3]) -> bool {
        let f = &self.frame;
        let origin = f.origin - f.apex;
        // `k + g·x` at the point `x` of the light's plane is `n·(x − apex)`.
        let trace = |n: Vec3| (n.dot(origin), Vec2::new(n.dot(f.u), n.dot(f.v)));
        // True when `k + g·x` exceeds the tolerance over the whole rectangle: at its corner where it
        // is least.
        let clear = |(k, g): (f32, Vec2)| {
            let least =
                Vec2::new(if g.x > 0.0 { self.lo.x } else { self.hi.x }, if g.y > 0.0 { self.lo.y } else { self.hi.y });
            k + g.dot(least) > self.eps * g.length()
        };
        let edge = |i: usize| {
            let n = w[i].cross(w[(i + 1) % 3]);
            // Positive away from the triangle.
            let n = if n.dot(w[(i + 2) % 3]) > 0.0 { -n } else { n };
            clear(trace(n))
        };
        let far_cut = || {
            let m = (w[1] - w[0]).cross(w[2] - w[0]);
            let e = m.dot(w[0]);
            let (m, e) = if e < 0.0 { (-m, -e) } else { (m, e) };
            let (k, g) = trace(m);
            e > 0.0 && clear((e / (1.0 - DEPTH_EPS) - k, -g))
        };
        edge(0) || edge(1) || edge(2) || far_cut()
    }

    /// True when the rectangle `[lo, hi]` meets the pieces' bounding rectangle.
    fn meets_rect(&self, lo: Vec2, hi: Vec2) -> bool {
        !(hi.x < self.lo.x || hi.y < self.lo.y || lo.x > self.hi.x || lo.y > self.hi.y)
    }

    /// [`ShadowBeam::occlude`] for a triangle wholly in the depth range, projected to `q`.
    fn occlude_projected(&mut self, q: &[Vec2; 3]) -> bool {
        let (lo, hi) = (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]));
        if !self.meets_rect(lo, hi) {
            return false;
        }
        self.split_pieces::<3>(q, lo, hi)
    }

    /// Remove from the pieces what the convex polygon `corners` (bounding rectangle `[lo, hi]`)
    /// hides. True when any piece was hit.
    fn split_pieces<const N: usize>(&mut self, corners: &[Vec2], lo: Vec2, hi: Vec2) -> bool {
        let (mut hit, mut dropped) = (false, false);
        let query = Vec4::new(hi.x, hi.y, -lo.x, -lo.y);
        // The polygon's edge lines, made when a piece's box first meets its box.
        let mut lines = None;
        // Pieces [0, end) are the ones from before this triangle; its miss parts are appended.
        let mut end = self.pieces.len();
        let mut i = 0;
        loop {
            // Skip to the next piece whose box meets the triangle's.
            i += self.boxes[i..end].iter().position(|b| b.cmple(query).all()).unwrap_or(end - i);
            if i >= end {
                break;
            }
            let lines = match lines {
                Some(ref lines) => lines,
                None => match EdgeLines::<N>::new(corners, self.eps * self.eps) {
                    Some(made) => lines.insert(made),
                    // A sliver or an edge-on triangle hides nothing.
                    None => return false,
                },
            };
            let piece = self.pieces[i];
            self.stats.intersections += 1;
            let len = self.pieces.len();
            let (pieces, boxes) = (&mut *self.pieces, &mut *self.boxes);
            match piece.split(lines, self.eps, &mut |q| {
                let (lo, hi) = q.bounds();
                let b = Self::rect(lo, hi);
                pieces.push(q);
                boxes.push(b);
            }) {
                Cover::Outside => {
                    self.pieces.truncate(len);
                    self.boxes.truncate(len);
                    i += 1;
                }
                Cover::Crossed if self.pieces.len() > len => {
                    // The last missed part takes this piece's place.
                    hit = true;
                    self.stats.hit_beams += 1;
                    self.stats.pieces += (self.pieces.len() - len) as u64;
                    self.pieces.swap_remove(i);
                    self.boxes.swap_remove(i);
                    i += 1;
                }
                Cover::Inside | Cover::Crossed => {
                    // Wholly hidden: move the last unvisited piece here, then drop this one.
                    (hit, dropped) = (true, true);
                    self.stats.hit_beams += 1;
                    end -= 1;
                    self.pieces.swap(i, end);
                    self.pieces.swap_remove(end);
                    self.boxes.swap(i, end);
                    self.boxes.swap_remove(end);
                }
            }
        }
        // Missed parts lie in the box of the piece they come from, so the bound holds until a
        // piece goes; recomputing it only then is cheaper than its extra rejections are worth.
        if dropped {
            self.union_boxes();
        }
        hit
    }
}
