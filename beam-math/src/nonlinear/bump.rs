//! Bump-mapped (perturbed) beams (000 §4 and §6.3): S1 rays perturbed by at most an angle δ, and the
//! D-expansion of the S1 bounding triangle (eq. 5, proof in App. B.5).

use super::beam::NonlinearBeam;
use super::bounding_triangle::{BeamBounds, BoundingTriangle};
use super::projection::s1_solutions;
use crate::collide::Cone;
use crate::float::Float;
use crate::shapes::{Ray, Triangle};
use glam::{Vec2, Vec3};

/// Unit direction `d` (on the side of unit normal `n`) rotated by the angle `δ·‖tilt‖` towards the
/// tangent direction `tilt` (a vector of length ≤ 1 in the frame `(u, n × u)`, as read from a bump
/// map); `d` itself when the rotated direction would leave the side of `n` by more than
/// [`super::MIN_ELEVATION`] allows.
#[must_use]
pub fn perturb(d: Vec3, n: Vec3, u: Vec3, tilt: Vec2, delta: f32) -> Vec3 {
    let len = tilt.length().min(1.0);
    if len == 0.0 {
        return d;
    }
    let v = n.cross(u);
    // Rotate d by angle a about the axis perpendicular to d and the tilt direction.
    let t = (tilt.x * u + tilt.y * v).normalize();
    let axis = d.cross(t).normalize_or_zero();
    let a = delta * len;
    let rotated = d * a.cos_() + axis.cross(d) * a.sin_() + axis * axis.dot(d) * (1.0 - a.cos_());
    if rotated.dot(n) >= super::beam::MIN_ELEVATION { rotated } else { d }
}

/// An S1 beam whose rays a bump map tilts by at most `delta` radians.
#[derive(Clone, Copy, Debug)]
pub struct BumpBeam {
    /// The unperturbed S1 beam.
    pub beam: NonlinearBeam,
    /// Maximum perturbation angle δ between a ray and its unperturbed cousin.
    pub delta: f32,
}

impl BumpBeam {
    /// The perturbed ray at base point `w`: the S1 ray rotated by the angle `δ·‖tilt‖` towards the
    /// tangent direction `tilt` (a vector of length ≤ 1 in the frame `(u, n × u)` of the base, as read
    /// from a bump map). The perturbed direction never leaves the inner side of the base plane.
    #[must_use]
    pub fn ray_at(&self, w: Vec3, tilt: Vec2) -> Ray {
        let ray = self.beam.ray_at(w);
        let u = (self.beam.base[1] - self.beam.base[0]).normalize();
        Ray::new(ray.origin, perturb(ray.direction.normalize(), self.beam.normal, u, tilt, self.delta))
    }

    /// `φ`: the largest angle between two rays of the unperturbed beam (attained between two
    /// boundary directions, which span the cone of all S1 directions).
    #[must_use]
    pub fn spread(&self) -> f32 {
        let d = self.beam.dirs;
        let c = d[0].dot(d[1]).min(d[1].dot(d[2])).min(d[0].dot(d[2]));
        c.clamp(-1.0, 1.0).acos_()
    }

    /// Bounding triangle for the perturbed beam (000 §6.3, eq. 5): the S1 bounding triangle expanded
    /// by `D = max‖QᵢPᵢⱼ‖·sin τ / sin(θ3 − τ)`, `τ = δ + φ`. When `θ3 ≤ τ` no finite `D` exists and
    /// the whole base is returned. `None` when the triangle lies behind the base.
    #[must_use]
    pub fn bounding_triangle(&self, bounds: &BeamBounds, tri: &Triangle) -> Option<BoundingTriangle> {
        self.bounding_triangle_with(bounds, tri, |q| self.beam.contains_s1(q))
    }

    /// [`Self::bounding_triangle`] with the vertices classified by `inside`, which must answer as
    /// the S1 beam's [`NonlinearBeam::contains_s1`] does.
    #[must_use]
    pub fn bounding_triangle_with(
        &self,
        bounds: &BeamBounds,
        tri: &Triangle,
        inside: impl FnMut(Vec3) -> bool,
    ) -> Option<BoundingTriangle> {
        let s1 = self.beam.bounding_triangle_with(bounds, tri, inside)?;
        if s1 == BoundingTriangle::BASE {
            return Some(s1);
        }
        let n = self.beam.normal;
        let tau = self.delta + self.spread();
        let theta2 = self.beam.dirs.iter().fold(1.0f32, |m, d| m.min(n.dot(*d))).clamp(-1.0, 1.0).asin_();
        let theta3 = if theta2 > tau {
            theta2
        } else {
            let theta1 = self.theta1(tri);
            if theta1 > tau {
                theta1
            } else {
                return Some(BoundingTriangle::BASE);
            }
        };
        let plane = self.beam.base_plane();
        let mut reach = 0.0f32;
        for q in tri.v {
            for d in &bounds.extremal {
                let p = super::affine::transfer(q, *d, plane)?;
                reach = reach.max(q.distance(p));
            }
        }
        let d = reach * tau.sin_() / (theta3 - tau).sin_();
        Some(s1.expanded(d, bounds.heights))
    }

    /// `θ1 = asin(min n·d_Qᵢ)` with `d_Qᵢ` the unit vector from the unperturbed projection of `Qᵢ`
    /// to `Qᵢ` (three cubics; only needed when `θ2 ≤ τ`).
    fn theta1(&self, tri: &Triangle) -> f32 {
        let b = &self.beam;
        let mut s = 1.0f32;
        for q in tri.v {
            let (sol, count) = s1_solutions(b.base.map(|v| v.as_dvec3()), b.dirs.map(|v| v.as_dvec3()), q.as_dvec3());
            let mut any = false;
            for &(w, t) in &sol[..count] {
                if t > 0.0 {
                    let p = b.base_triangle().point(w.as_vec3());
                    s = s.min(b.normal.dot((q - p).normalize_or_zero()));
                    any = true;
                }
            }
            if !any {
                return -core::f32::consts::FRAC_PI_2;
            }
        }
        s.clamp(-1.0, 1.0).asin_()
    }

    /// Bounding cone of the perturbed beam: the S1 cone widened by δ (000 App. A).
    #[must_use]
    pub fn bounding_cone(&self) -> Cone {
        self.beam.bounding_cone(&self.beam.dirs, self.delta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perturbation_angle_is_bounded_by_delta() {
        let beam = NonlinearBeam::s1(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::new(-0.2, -0.2, 1.0), Vec3::new(0.2, 0.0, 1.0), Vec3::new(0.0, 0.2, 1.0)],
        )
        .unwrap();
        let bump = BumpBeam { beam, delta: 0.1 };
        let w = Vec3::new(0.3, 0.3, 0.4);
        let base = beam.ray_at(w).direction.normalize();
        for k in 0..16 {
            let a = k as f32 * 0.4;
            let tilted = bump.ray_at(w, Vec2::new(a.cos(), a.sin())).direction;
            let angle = base.dot(tilted).clamp(-1.0, 1.0).acos();
            assert!((angle - 0.1).abs() < 1e-3, "{angle}");
        }
        assert!(bump.spread() > 0.0);
    }
}
