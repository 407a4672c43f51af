//! Where the light arriving at an S-mesh face comes from, and its directions at the face's
//! vertices (000 §7.2).

use beam_math::glam::{Mat3, Vec3};
use beam_scene::nonlinear::{Beam, SFace};

/// Where the light arriving at an S-mesh face comes from: the eye, or a parent beam.
#[derive(Clone, Copy)]
pub(super) enum Source<'a> {
    Eye(Vec3),
    Beam(&'a Beam),
}

impl Source<'_> {
    /// Unit directions of the light arriving at the vertices of `f`: from the eye; from a parent
    /// beam, the affine fit over `f`'s barycentric coordinates of the directions of the parent's
    /// texel rays that hit `f` (`samples`: barycentric point, unit direction), exact for the
    /// directions an S1 parent carries across a flat face; when the samples do not span the face,
    /// the parent's rays through the vertices (projection, extrapolated past the parent's base).
    pub(super) fn directions_to(self, f: &SFace, samples: &[(Vec3, Vec3)]) -> Option<[Vec3; 3]> {
        let beam = match self {
            Self::Eye(eye) => {
                let [a, b, c] = f.v.map(|v| (v - eye).try_normalize());
                return Some([a?, b?, c?]);
            }
            Self::Beam(beam) => beam,
        };
        let gram: Mat3 = samples.iter().map(|(w, _)| Mat3::from_cols(*w * w.x, *w * w.y, *w * w.z)).sum();
        if samples.len() >= 3 && gram.determinant() > 1e-6 * samples.len().pow(3) as f32 {
            // Least squares for d(w) = Σ wᵢ Dᵢ: (Σ w wᵀ) [D₀ D₁ D₂]ᵀ = Σ w dᵀ.
            let moment: Mat3 = samples.iter().map(|(w, d)| Mat3::from_cols(*d * w.x, *d * w.y, *d * w.z)).sum();
            let fit = moment * gram.inverse();
            let [a, b, c] = [fit.x_axis, fit.y_axis, fit.z_axis].map(Vec3::try_normalize);
            if let (Some(a), Some(b), Some(c)) = (a, b, c) {
                return Some([a, b, c]);
            }
        }
        let [a, b, c] = f.v.map(|v| beam.direction_through(v));
        Some([a?, b?, c?])
    }
}
