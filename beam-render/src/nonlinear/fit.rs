//! The least-squares fit of the light arriving at an S-mesh face to its vertices (000 §7.2): the
//! sums a backend or the host adds a face's samples to, and the directions they give.

use beam_math::glam::{Mat3, Vec3};

/// The sums of [`Fit::directions`]' least-squares fit over the samples (barycentric point `w`,
/// unit direction `d`) of the rays arriving at a face: Σ w wᵀ, Σ d wᵀ and their number. A face's
/// samples are summed as they come, never kept: on the host in the samples' order, on beam-gpu in
/// fixed point ([`Fit::from_sums`]); each way the same samples give the same bits, frame after
/// frame (the beams made from them are looked up by their bits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
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
    /// The fit of `samples` samples whose sums a backend made: `gram` Σ w wᵀ, `moment` Σ d wᵀ
    /// (columns: Σ w·w₀ …, Σ d·w₀ …).
    #[must_use]
    pub fn from_sums(gram: Mat3, moment: Mat3, samples: usize) -> Self {
        Self { gram, moment, samples }
    }

    /// Add the sample at barycentric point `w` with unit direction `d`.
    pub fn add(&mut self, w: Vec3, d: Vec3) {
        self.gram += Mat3::from_cols(w * w.x, w * w.y, w * w.z);
        self.moment += Mat3::from_cols(d * w.x, d * w.y, d * w.z);
        self.samples += 1;
    }

    /// Its sums: Σ w wᵀ and Σ d wᵀ.
    #[must_use]
    pub fn sums(&self) -> (Mat3, Mat3) {
        (self.gram, self.moment)
    }

    /// How many samples were added.
    #[must_use]
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// The unit directions at the face's vertices of the affine fit over barycentric coordinates
    /// of the samples' directions, d(w) = Σ wᵢ Dᵢ: exact for the directions an S1 parent carries
    /// across a flat face. `None` where the samples do not span the face (fewer than three, or a
    /// Gram matrix near singular) or a fitted direction is zero.
    #[must_use]
    pub fn directions(&self) -> Option<[Vec3; 3]> {
        let Self { gram, moment, samples } = *self;
        // (A NaN determinant spans nothing.)
        let spans = samples >= 3 && gram.determinant() > 1e-6 * samples.pow(3) as f32;
        // Least squares: (Σ w wᵀ) [D₀ D₁ D₂]ᵀ = Σ w dᵀ.
        let fit = spans.then(|| moment * gram.inverse())?;
        let [a, b, c] = [fit.x_axis, fit.y_axis, fit.z_axis].map(Vec3::try_normalize);
        Some([a?, b?, c?])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of the directions an affine field carries over a face.
    fn samples() -> Vec<(Vec3, Vec3)> {
        let at = [Vec3::Z, Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.0, 0.3, 1.0)];
        (0..40)
            .map(|i| {
                let (u, v) = ((i % 7) as f32 / 7.0, (i / 7) as f32 / 7.0 * (1.0 - (i % 7) as f32 / 7.0));
                let w = Vec3::new(1.0 - u - v, u, v);
                (w, (w.x * at[0] + w.y * at[1] + w.z * at[2]).normalize())
            })
            .collect()
    }

    /// A fit starts from zero sums, and its sums are those of its samples, bit for bit (summed from
    /// zero in their order, as `Iterator::sum` does).
    #[test]
    fn fit_sums_its_samples() {
        let samples = samples();
        let mut fit = Fit::default();
        assert_eq!((fit.gram, fit.moment, fit.samples()), (Mat3::ZERO, Mat3::ZERO, 0));
        for &(w, d) in &samples {
            fit.add(w, d);
        }
        let gram: Mat3 = samples.iter().map(|(w, _)| Mat3::from_cols(*w * w.x, *w * w.y, *w * w.z)).sum();
        let moment: Mat3 = samples.iter().map(|(w, d)| Mat3::from_cols(*d * w.x, *d * w.y, *d * w.z)).sum();
        assert_eq!(fit, Fit::from_sums(gram, moment, samples.len()));
    }

    /// The fit of directions that vary affinely over the face (before normalisation) gives back
    /// their directions at the vertices; two samples, or samples on one line, give none.
    #[test]
    fn fit_recovers_an_affine_field() {
        let mut fit = Fit::default();
        for (w, d) in samples() {
            fit.add(w, d);
        }
        let at = [Vec3::Z, Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.0, 0.3, 1.0)].map(Vec3::normalize);
        let got = fit.directions().expect("the samples span the face");
        for (g, a) in got.iter().zip(at) {
            assert!(g.angle_between(a) < 0.02, "{g} vs {a}");
        }
        let mut line = Fit::default();
        for i in 0..10 {
            let t = i as f32 / 9.0;
            line.add(Vec3::new(1.0 - t, t, 0.0), Vec3::Z);
        }
        assert_eq!(line.directions(), None);
        let mut two = Fit::default();
        two.add(Vec3::X, Vec3::Z);
        two.add(Vec3::Y, Vec3::Z);
        assert_eq!(two.directions(), None);
    }
}
