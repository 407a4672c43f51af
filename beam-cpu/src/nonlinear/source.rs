//! Where the light arriving at an S-mesh face comes from, and its directions at the face's
//! vertices (000 §7.2).

use beam_math::glam::{Mat3, Vec3};
use beam_scene::nonlinear::{Beam, SFace};

/// Where the light arriving at an S-mesh face comes from: the eye, or a parent beam.
#[derive(Clone, Copy)]
pub(super) enum Source {
    Eye(Vec3),
    Parent,
}

impl Source {
    /// Unit directions of the light arriving at the vertices of `f` where they need no projection:
    /// `Some` of those from the eye, or from a parent beam of the affine fit over `f`'s barycentric
    /// coordinates of the directions of the parent's texel rays that hit `f` (`fit`'s samples:
    /// barycentric point, unit direction), exact for the directions an S1 parent carries across a
    /// flat face; `None` where the samples do not span the face, and the directions are the
    /// parent's rays through the vertices ([`through`]).
    pub(super) fn fitted(self, f: &SFace, fit: &Fit) -> Option<Option<[Vec3; 3]>> {
        if let Self::Eye(eye) = self {
            let [a, b, c] = f.v.map(|v| (v - eye).try_normalize());
            return Some(a.zip(b).zip(c).map(|((a, b), c)| [a, b, c]));
        }
        let Fit { gram, moment, samples } = *fit;
        if samples >= 3 && gram.determinant() > 1e-6 * samples.pow(3) as f32 {
            // Least squares for d(w) = Σ wᵢ Dᵢ: (Σ w wᵀ) [D₀ D₁ D₂]ᵀ = Σ w dᵀ.
            let fit = moment * gram.inverse();
            let [a, b, c] = [fit.x_axis, fit.y_axis, fit.z_axis].map(Vec3::try_normalize);
            if let (Some(a), Some(b), Some(c)) = (a, b, c) {
                return Some(Some([a, b, c]));
            }
        }
        None
    }
}

/// Unit directions of `beam`'s rays through the vertices of `f` (projection, 000 §5, extrapolated
/// past the beam's base): three Newton projections, which the tree keeps from one frame to the
/// next ([`super::trace::ThroughMemo`]).
pub(super) fn through(beam: &Beam, f: &SFace) -> Option<[Vec3; 3]> {
    let [a, b, c] = f.v.map(|v| beam.direction_through(v));
    Some([a?, b?, c?])
}

/// The sums of [`Source::fitted`]'s least-squares fit over the samples (barycentric point
/// `w`, unit direction `d`) of the rays arriving at a face, added in the samples' order: Σ w wᵀ,
/// Σ d wᵀ and their number. A face's samples are summed as they come, never kept.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Fit {
    gram: Mat3,
    moment: Mat3,
    samples: usize,
}

impl Default for Fit {
    /// No samples: zero sums (not glam's default `Mat3`, the identity).
    fn default() -> Self {
        Self { gram: Mat3::ZERO, moment: Mat3::ZERO, samples: 0 }
    }
}

impl Fit {
    /// Add the sample at barycentric point `w` with unit direction `d`.
    pub(super) fn add(&mut self, w: Vec3, d: Vec3) {
        self.gram += Mat3::from_cols(w * w.x, w * w.y, w * w.z);
        self.moment += Mat3::from_cols(d * w.x, d * w.y, d * w.z);
        self.samples += 1;
    }

    /// How many samples were added.
    pub(super) fn samples(&self) -> usize {
        self.samples
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fit starts from zero sums, and its sums are those of its samples, bit for bit (summed from
    /// zero in their order, as `Iterator::sum` does).
    #[test]
    fn fit_sums_its_samples() {
        let samples: Vec<(Vec3, Vec3)> = (0..40)
            .map(|i| {
                let (u, v) = ((i % 7) as f32 / 7.0, (i / 7) as f32 / 7.0 * (1.0 - (i % 7) as f32 / 7.0));
                let w = Vec3::new(1.0 - u - v, u, v);
                (w, (w.x * Vec3::Z + w.y * Vec3::new(0.3, 0.0, 1.0) + w.z * Vec3::new(0.0, 0.3, 1.0)).normalize())
            })
            .collect();
        let mut fit = Fit::default();
        assert_eq!((fit.gram, fit.moment, fit.samples()), (Mat3::ZERO, Mat3::ZERO, 0));
        for &(w, d) in &samples {
            fit.add(w, d);
        }
        let gram: Mat3 = samples.iter().map(|(w, _)| Mat3::from_cols(*w * w.x, *w * w.y, *w * w.z)).sum();
        let moment: Mat3 = samples.iter().map(|(w, d)| Mat3::from_cols(*d * w.x, *d * w.y, *d * w.z)).sum();
        assert_eq!((fit.gram, fit.moment, fit.samples()), (gram, moment, samples.len()));
    }
}
