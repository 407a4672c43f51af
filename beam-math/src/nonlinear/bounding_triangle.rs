//! Bounding triangle estimation (000 §6, Algorithms 3 and 4): a triangle on the beam base that
//! contains the (curved, possibly multi-part) projection of a scene triangle, for rasterization.
//!
//! Every bounding triangle here has its edges parallel to the base edges, so it is stored as three
//! numbers: the lower bounds `m_k` of the barycentric coordinates, `{ω : ω_k ≥ m_k}`. An ε-expansion
//! by a distance ε moves edge `k` by `ε/h_k` in `ω_k` (`h_k` the height of the reference triangle).
//! The same holds for triangles built on an affine plane `Πa(t)`: by the barycentric invariance of
//! 000 §5 the coordinates carry over to the base unchanged (`F = Ω⁻¹(Ω(E, Δa), Δb)`).

use super::affine::transfer;
use super::beam::NonlinearBeam;
use super::parameterization::Interpolant;
use super::projection::s1_solutions;
use super::threshold::ThresholdPlane;
use crate::shapes::{Plane, Triangle};
use glam::{Mat3, Vec3};

/// Which branch of Alg. 3 / 4 produced a bounding triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundingCase {
    /// The scene triangle straddles the beam boundary: the whole base.
    BruteForce,
    /// Transfers onto the base plane `Πb` (the algorithm of \[11\]).
    General,
    /// Transfers onto the affine plane through the top of the triangle, mapped back to the base.
    UniqueProjection,
}

/// A bounding triangle on the base: `{ω : ω_k ≥ lower_k}` in base barycentric coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingTriangle {
    /// Lower bounds `m_k` of the barycentric coordinates; `0` is the base triangle itself.
    pub lower: Vec3,
    /// The branch of the algorithm that produced it.
    pub case: BoundingCase,
}

impl BoundingTriangle {
    /// The whole base triangle (the brute-force case).
    pub const BASE: Self = Self { lower: Vec3::ZERO, case: BoundingCase::BruteForce };

    /// Corners in base barycentric coordinates: corner `i` has `ω_k = m_k` for `k ≠ i`.
    #[must_use]
    pub fn corners(&self) -> [Vec3; 3] {
        let m = self.lower;
        [
            Vec3::new(1.0 - m.y - m.z, m.y, m.z),
            Vec3::new(m.x, 1.0 - m.x - m.z, m.z),
            Vec3::new(m.x, m.y, 1.0 - m.x - m.y),
        ]
    }

    /// Corners as points on the base plane.
    #[must_use]
    pub fn points(&self, base: &Triangle) -> [Vec3; 3] {
        self.corners().map(|w| base.point(w))
    }

    /// True when the base point with barycentric coordinates `w` is inside (with tolerance `tol`).
    #[must_use]
    pub fn contains(&self, w: Vec3, tol: f32) -> bool {
        w.cmpge(self.lower - Vec3::splat(tol)).all()
    }

    /// Area relative to the base triangle: `(1 − Σ m_k)²`.
    #[must_use]
    pub fn area_ratio(&self) -> f32 {
        let s = 1.0 - self.lower.element_sum();
        s * s
    }

    /// Area of the part inside the base triangle, relative to the base: `(1 − Σ max(m_k, 0))²`.
    #[must_use]
    pub fn clipped_area_ratio(&self) -> f32 {
        let s = (1.0 - self.lower.max(Vec3::ZERO).element_sum()).max(0.0);
        s * s
    }

    /// This triangle with every edge moved outwards by the distance `d`, for a reference triangle
    /// of heights `h` (ExpandedBoundingTriangle of Alg. 4).
    #[must_use]
    pub fn expanded(self, d: f32, h: Vec3) -> Self {
        Self { lower: self.lower - Vec3::splat(d) / h, ..self }
    }
}

/// The smallest triangle with edges parallel to a reference triangle that contains points given by
/// their barycentric coordinates in it, each edge then moved out by `expand_k` in `ω_k`: the
/// `BoundingTriangle({P_ij})` step of Alg. 3. Returns the corners in the reference's coordinates.
#[must_use]
pub fn enclosing_triangle(bary: impl Iterator<Item = Vec3>, expand: Vec3) -> [Vec3; 3] {
    let m = bary.fold(Vec3::INFINITY, Vec3::min) - expand;
    BoundingTriangle { lower: m, case: BoundingCase::General }.corners()
}

/// Per-beam quantities of Alg. 3 / 4 ("all quantities above are pre-computed per B").
#[derive(Clone, Copy, Debug)]
pub struct BeamBounds {
    /// Extremal directions `d̂ᵢ` (unit).
    pub extremal: [Vec3; 3],
    /// The threshold plane `Π_T`.
    pub threshold: ThresholdPlane,
    /// Maximum origin offset `μ_b` (eq. 4).
    pub mu_b: f32,
    /// Maximum direction offset `μ_d` (eq. 4).
    pub mu_d: f32,
    /// Heights of the base triangle.
    pub heights: Vec3,
}

impl<L: Interpolant> NonlinearBeam<L> {
    /// The per-beam quantities of Alg. 3 / 4.
    #[must_use]
    pub fn bounds(&self) -> BeamBounds {
        let (mu_b, mu_d) = self.max_offsets();
        BeamBounds {
            extremal: self.extremal_directions(),
            threshold: self.threshold_plane_with((mu_b, mu_d)),
            mu_b,
            mu_d,
            heights: self.heights(),
        }
    }

    /// Bounding triangle of the projection of `tri` (000 Alg. 3 for S1, Alg. 4 for S^n). `None`
    /// when the triangle lies wholly behind the base plane (no ray reaches it; beyond the paper).
    ///
    /// Brute force when the vertices are not all inside or all outside the beam (classified with the
    /// S1 beam through the boundary rays); the general case when the triangle is not above the
    /// threshold plane; otherwise the unique-projection case. The unique-projection case is used only
    /// when every `d̂ⱼ` points to the same side of `Πa(t_top)`, which is what its proof (App. B.4)
    /// needs; otherwise it falls back to the general case.
    #[must_use]
    pub fn bounding_triangle(&self, bounds: &BeamBounds, tri: &Triangle) -> Option<BoundingTriangle> {
        self.bounding_triangle_with(bounds, tri, |q| self.contains_s1(q))
    }

    /// [`Self::bounding_triangle`] with the vertices classified by `inside`, which must answer as
    /// [`Self::contains_s1`] does (a memo of it, for triangles that share vertices).
    #[must_use]
    pub fn bounding_triangle_with(
        &self,
        bounds: &BeamBounds,
        tri: &Triangle,
        mut inside: impl FnMut(Vec3) -> bool,
    ) -> Option<BoundingTriangle> {
        if self.is_behind(bounds, tri) {
            return None;
        }
        let first = inside(tri.v[0]);
        if inside(tri.v[1]) != first || inside(tri.v[2]) != first {
            return Some(BoundingTriangle::BASE);
        }
        if !bounds.threshold.is_below(tri) {
            if let Some(b) = self.unique_projection_case(bounds, tri) {
                return Some(b);
            }
        }
        Some(self.general_case(bounds, tri))
    }

    /// Bounding triangle by the general case alone, for every triangle: the algorithm of \[11\] that
    /// 000 Fig. 7 compares against. `None` when the triangle is wholly behind the base.
    #[must_use]
    pub fn bounding_triangle_general(&self, bounds: &BeamBounds, tri: &Triangle) -> Option<BoundingTriangle> {
        (!self.is_behind(bounds, tri)).then(|| self.general_case(bounds, tri))
    }

    fn is_behind(&self, bounds: &BeamBounds, tri: &Triangle) -> bool {
        let plane = self.base_plane();
        tri.v.iter().all(|&q| plane.eval(q) < -bounds.mu_b)
    }

    /// General case: the nine transfers `P_ij` of `Qᵢ` in `d̂ⱼ` onto `Πb`, enclosed and expanded by
    /// `ε = μ_b / sin θ_min` (Alg. 4 with `t = 0`).
    fn general_case(&self, bounds: &BeamBounds, tri: &Triangle) -> BoundingTriangle {
        let plane = self.base_plane();
        let base = self.base_triangle();
        match enclose_transfers(tri, &bounds.extremal, plane, &base, bounds.mu_b, &bounds.heights) {
            Some(lower) => BoundingTriangle { lower, case: BoundingCase::General },
            None => BoundingTriangle::BASE,
        }
    }

    /// Unique-projection case: transfers onto `Πa(t_top)`, the affine plane through the top of the
    /// triangle (largest `t` over its vertices), enclosed, expanded by `(μ_b + t·μ_d)/sin θ_min`.
    fn unique_projection_case(&self, bounds: &BeamBounds, tri: &Triangle) -> Option<BoundingTriangle> {
        let base = self.base.map(|v| v.as_dvec3());
        let dirs = self.dirs.map(|v| v.as_dvec3());
        let mut t_top = f64::NEG_INFINITY;
        for q in tri.v {
            let (sol, n) = s1_solutions(base, dirs, q.as_dvec3());
            t_top = sol[..n].iter().fold(t_top, |m, s| m.max(s.1));
        }
        let t_top = t_top as f32;
        if !(t_top > bounds.threshold.t_max) || !t_top.is_finite() {
            return None;
        }
        let affine = self.affine_triangle(t_top);
        let plane = self.affine_plane(t_top);
        let side = bounds.extremal.map(|d| plane.normal.dot(d));
        let same_side = side.iter().all(|&s| s > 0.0) || side.iter().all(|&s| s < 0.0);
        if !same_side {
            return None;
        }
        let mu = bounds.mu_b + t_top * bounds.mu_d;
        let lower = enclose_transfers(tri, &bounds.extremal, plane, &affine, mu, &super::beam::heights(&affine))?;
        Some(BoundingTriangle { lower, case: BoundingCase::UniqueProjection })
    }
}

/// Lower barycentric bounds (w.r.t. `reference`, lying on `plane`) of the transfers of the triangle's
/// vertices in every direction, expanded by `mu / sin θ_min` with `θ_min` the smallest angle between
/// a direction and the plane.
fn enclose_transfers(
    tri: &Triangle,
    dirs: &[Vec3; 3],
    plane: Plane,
    reference: &Triangle,
    mu: f32,
    heights: &Vec3,
) -> Option<Vec3> {
    let n = plane.normal.normalize();
    let sin_min = dirs.iter().fold(f32::INFINITY, |m, d| m.min(n.dot(*d).abs() / d.length()));
    if !(sin_min > 0.0) {
        return None;
    }
    let mut lower = Vec3::INFINITY;
    for q in tri.v {
        for d in dirs {
            let h = transfer(q, *d, plane)?;
            lower = lower.min(reference.barycentric(h)?);
        }
    }
    let eps = mu / sin_min;
    let lower = lower - Vec3::splat(eps) / *heights;
    lower.is_finite().then_some(lower)
}

/// Barycentric coordinates of `w` (given in base coordinates) relative to a bounding triangle's
/// corners; used by tests and by the GPU conformance checks.
#[must_use]
pub fn relative_coordinates(corners: &[Vec3; 3], w: Vec3) -> Vec3 {
    Mat3::from_cols(corners[0], corners[1], corners[2]).inverse() * w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diverging() -> NonlinearBeam {
        NonlinearBeam::s1(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::new(-0.3, -0.3, 1.0), Vec3::new(0.4, -0.1, 1.0), Vec3::new(-0.1, 0.5, 1.0)],
        )
        .unwrap()
    }

    #[test]
    fn small_far_triangle_uses_unique_projection_and_is_tight() {
        let beam = diverging();
        let bounds = beam.bounds();
        let c = beam.ray_at(Vec3::splat(1.0 / 3.0)).at(20.0);
        let tri = Triangle::new(c, c + Vec3::new(0.2, 0.0, 0.0), c + Vec3::new(0.0, 0.2, 0.05));
        let ours = beam.bounding_triangle(&bounds, &tri).unwrap();
        let general = beam.bounding_triangle_general(&bounds, &tri).unwrap();
        assert_eq!(ours.case, BoundingCase::UniqueProjection);
        assert!(ours.area_ratio() < general.area_ratio() / 10.0, "{} vs {}", ours.area_ratio(), general.area_ratio());
    }

    #[test]
    fn straddling_triangle_gets_the_whole_base() {
        let beam = diverging();
        let bounds = beam.bounds();
        let c = beam.ray_at(Vec3::splat(1.0 / 3.0)).at(2.0);
        let tri = Triangle::new(c, c + Vec3::new(30.0, 0.0, 0.0), c + Vec3::new(0.0, 0.1, 0.0));
        assert_eq!(beam.bounding_triangle(&bounds, &tri), Some(BoundingTriangle::BASE));
    }

    #[test]
    fn triangle_behind_the_base_is_culled() {
        let beam = diverging();
        let tri = Triangle::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(1.0, 0.0, -1.0), Vec3::new(0.0, 1.0, -2.0));
        assert_eq!(beam.bounding_triangle(&beam.bounds(), &tri), None);
    }

    #[test]
    fn corners_and_areas() {
        let b = BoundingTriangle { lower: Vec3::new(-0.5, 0.0, 0.0), case: BoundingCase::General };
        assert_eq!(b.area_ratio(), 2.25);
        assert_eq!(b.clipped_area_ratio(), 1.0);
        let c = b.corners();
        assert_eq!(c[0], Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(c[1], Vec3::new(-0.5, 1.5, 0.0));
        let rel = relative_coordinates(&c, Vec3::new(0.0, 0.5, 0.5));
        assert!(rel.min_element() >= 0.0);
    }
}
