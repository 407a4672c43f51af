//! The polygon beam of 001 §3.1: an apex with 3–4 corner rays (more after splits), represented, as
//! the paper does, by the corner points on a reference plane (the image plane for primary beams, a
//! plane at the light for shadow beams).

use crate::collide::ConvexPolygon;
use crate::shapes::Ray;
use glam::{Vec2, Vec3};

/// Storage capacity of a cross-section. Splitting adds at most one corner per triangle edge and
/// [`super::KEEP_CORNERS`] bounds what a split returns, so this never overflows.
pub const MAX_CORNERS: usize = 16;

/// A convex cross-section on the reference plane, in the plane's `(u, v)` coordinates.
pub type Section = ConvexPolygon<MAX_CORNERS>;

/// The frame shared by a beam and all beams split from it: apex and reference plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamFrame {
    /// Common origin of all rays of the beam.
    pub apex: Vec3,
    /// A point of the reference plane, origin of the 2D coordinates.
    pub origin: Vec3,
    /// Unit first axis of the reference plane.
    pub u: Vec3,
    /// Unit second axis of the reference plane.
    pub v: Vec3,
    /// Unit plane normal, pointing away from the apex.
    pub normal: Vec3,
    /// Distance from the apex to the reference plane, `> 0`.
    pub distance: f32,
}

impl BeamFrame {
    /// The frame with apex `apex` and reference plane through `origin` with normal `normal` and first
    /// axis along `u_hint` (projected into the plane). `None` when the apex lies on the plane or the
    /// input is degenerate.
    #[must_use]
    pub fn new(apex: Vec3, origin: Vec3, normal: Vec3, u_hint: Vec3) -> Option<Self> {
        let mut normal = normal.try_normalize()?;
        let mut distance = (origin - apex).dot(normal);
        if distance < 0.0 {
            normal = -normal;
            distance = -distance;
        }
        if !(distance > 0.0) || !apex.is_finite() || !origin.is_finite() {
            return None;
        }
        let u =
            (u_hint - u_hint.dot(normal) * normal).try_normalize().unwrap_or_else(|| normal.any_orthonormal_vector());
        let v = normal.cross(u);
        Some(Self { apex, origin, u, v, normal, distance })
    }

    /// Depth of `p` in units of the plane distance: `(p − apex)·n / distance` (1 on the plane).
    #[must_use]
    pub fn depth(&self, p: Vec3) -> f32 {
        (p - self.apex).dot(self.normal) / self.distance
    }

    /// Central projection of `p` through the apex onto the reference plane, in `(u, v)` coordinates.
    /// Only meaningful for points in front of the apex (`depth > 0`).
    #[must_use]
    pub fn project(&self, p: Vec3) -> Vec2 {
        let q = self.apex + (p - self.apex) / self.depth(p);
        let r = q - self.origin;
        Vec2::new(r.dot(self.u), r.dot(self.v))
    }

    /// The 3D point of the reference plane with coordinates `c`.
    #[must_use]
    pub fn point(&self, c: Vec2) -> Vec3 {
        self.origin + c.x * self.u + c.y * self.v
    }

    /// Outward normals of the four planes through the apex and the sides of the rectangle `[lo, hi]`
    /// of the reference plane: a point `x` is inside the pyramid where `n·(x − apex) ≤ 0` for all four.
    #[must_use]
    pub fn side_normals(&self, lo: Vec2, hi: Vec2) -> [Vec3; 4] {
        let q = [Vec2::new(lo.x, lo.y), Vec2::new(hi.x, lo.y), Vec2::new(hi.x, hi.y), Vec2::new(lo.x, hi.y)]
            .map(|c| self.point(c) - self.apex);
        let mid = self.point(0.5 * (lo + hi)) - self.apex;
        core::array::from_fn(|i| {
            let n = q[i].cross(q[(i + 1) % 4]);
            if n.dot(mid) > 0.0 { -n } else { n }
        })
    }

    /// The ray from the apex through the plane point `c` (direction reaches the plane at `t = 1`).
    #[must_use]
    pub fn ray(&self, c: Vec2) -> Ray {
        Ray::new(self.apex, self.point(c) - self.apex)
    }
}

/// A polygon beam: a frame and a convex cross-section on its reference plane (001 §3.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyBeam {
    /// Apex and reference plane.
    pub frame: BeamFrame,
    /// Cross-section on the reference plane, counter-clockwise in `(u, v)`.
    pub section: Section,
}

impl PolyBeam {
    /// A beam from an apex and 3D corner points on (or projected onto) the reference plane of
    /// `frame`. Corners are reordered counter-clockwise. `None` for fewer than 3 or more than
    /// [`MAX_CORNERS`] corners, or corners behind the apex.
    #[must_use]
    pub fn new(frame: BeamFrame, corners: &[Vec3]) -> Option<Self> {
        let mut section = Section::new();
        for &c in corners {
            if !(frame.depth(c) > 0.0) {
                return None;
            }
            section.push(frame.project(c)).ok()?;
        }
        if section.len() < 3 {
            return None;
        }
        if section.signed_area() < 0.0 {
            let n = section.len();
            let mut rev = Section::new();
            for i in (0..n).rev() {
                rev.push(section.vertices()[i]).ok()?;
            }
            section = rev;
        }
        Some(Self { frame, section })
    }

    /// The corner rays (001 §3.1).
    pub fn corner_rays(&self) -> impl Iterator<Item = Ray> + '_ {
        self.section.vertices().iter().map(|&c| self.frame.ray(c))
    }

    /// Cross-section area on the reference plane (shoelace, 004 App. A.10).
    #[must_use]
    pub fn area(&self) -> f32 {
        self.section.area()
    }
}
