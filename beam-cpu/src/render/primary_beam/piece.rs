//! A piece of the eye beam (the part of its cross-section that sees one triangle) and the inverse
//! depth of the plane it sees, shared by the eye tracer and the node test ([`super::node_view`]).

use beam_math::Triangle;
use beam_math::glam::{Vec2, Vec3, Vec4};
use beam_math::polybeam::{BeamFrame, Section};

/// Near clipping depth of the eye beam, in units of the image-plane distance.
pub const NEAR: f32 = 1e-4;

/// Planes whose inverse depths differ by at most this fraction over a piece count as the same
/// plane there: the one already seen keeps the piece (rays pick either, by rounding).
const COPLANAR: f32 = 1e-5;

/// `1/s` of a plane as an affine function `k0 + k·c` of the image-plane point `c` (larger = nearer),
/// and the plane itself, `n·x = w` with the eye where `n·x > w`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct InverseDepth {
    pub(super) k0: f32,
    pub(super) k: Vec2,
    plane: Vec4,
}

impl InverseDepth {
    /// For the plane through `tri`; `None` when the plane passes through the apex (seen edge-on).
    pub(super) fn of(frame: &BeamFrame, tri: &Triangle) -> Option<Self> {
        let n = tri.scaled_normal();
        let h = n.dot(frame.apex - tri.v[0]);
        if h.abs() <= 1e-12 * n.length() * (frame.apex - tri.v[0]).length() {
            return None;
        }
        // s(c) = −h / (n·w(c)) with w(c) = origin − apex + c.x·u + c.y·v.
        let k0 = -n.dot(frame.origin - frame.apex) / h;
        let facing = (n * h.signum()).normalize();
        let plane = facing.extend(facing.dot(tri.v[0]));
        Some(Self { k0, k: Vec2::new(-n.dot(frame.u), -n.dot(frame.v)) / h, plane })
    }

    /// True when the box `[min, max]` lies wholly behind the plane, seen from the eye.
    pub(super) fn hides(&self, min: Vec3, max: Vec3) -> bool {
        let n = self.plane.truncate();
        let front = n.dot(Vec3::select(n.cmpgt(Vec3::ZERO), max, min));
        front - self.plane.w < -1e-5 * (front.abs() + self.plane.w.abs())
    }

    pub(super) fn at(&self, c: Vec2) -> f32 {
        self.k0 + self.k.dot(c)
    }

    pub(super) fn minus(&self, o: &Self) -> Self {
        Self { k0: self.k0 - o.k0, k: self.k - o.k, plane: self.plane }
    }
}

/// A piece of the eye beam and the triangle it sees (none: the background).
#[derive(Clone, Copy, Debug)]
pub struct Piece {
    /// Cross-section on the image plane.
    pub section: Section,
    /// The visible triangle.
    pub prim: Option<u32>,
    pub(super) depth: Option<InverseDepth>,
    /// Bounding rectangle of the section.
    pub(super) lo: Vec2,
    pub(super) hi: Vec2,
    /// Smallest `1/s` over the section, at its farthest point (0: unbounded, the background).
    pub(super) far_inv: f32,
    /// Area of the section.
    pub(super) area: f32,
}

impl Piece {
    pub(super) fn new(section: Section, prim: Option<u32>, depth: Option<InverseDepth>) -> Self {
        let (lo, hi) = section.bounds();
        let far_inv =
            depth.map_or(0.0, |d| section.vertices().iter().fold(f32::INFINITY, |m, &c| m.min(d.at(c))).max(0.0));
        Self { section, prim, depth, lo, hi, far_inv, area: section.area() }
    }

    /// No piece: what a piece joined into another leaves behind (it meets nothing).
    pub(super) fn gone() -> Self {
        Self {
            section: Section::new(),
            prim: None,
            depth: None,
            lo: Vec2::INFINITY,
            hi: Vec2::NEG_INFINITY,
            far_inv: 0.0,
            area: 0.0,
        }
    }

    /// True for a piece joined into another.
    pub(super) fn is_gone(&self) -> bool {
        self.section.is_empty()
    }

    /// Another cross-section seeing the same triangle at the same depths.
    #[must_use]
    pub fn with_section(&self, section: Section) -> Self {
        Self::new(section, self.prim, self.depth)
    }

    /// How much nearer a plane of inverse depth `depth` is than the piece's own, over the piece:
    /// the smallest and largest of their difference `g` (attained at corners: `g` is affine),
    /// snapped to zero within [`COPLANAR`] of the piece's inverse depth, so that rounding never
    /// lets one of two coplanar triangles cut the other's pieces into slivers.
    pub(super) fn nearer(&self, owner: &InverseDepth, depth: &InverseDepth) -> (f32, f32) {
        let g = depth.minus(owner);
        let (mut min, mut max, mut size) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
        for &c in self.section.vertices() {
            let v = g.at(c);
            (min, max, size) = (min.min(v), max.max(v), size.max(owner.at(c).abs()));
        }
        let tol = COPLANAR * size;
        let snap = |v: f32| if v.abs() <= tol { 0.0 } else { v };
        (snap(min), snap(max))
    }
}
