//! Where the light arriving at an S-mesh face comes from, and its directions at the face's
//! vertices (000 §7.2).

use beam_math::glam::Vec3;
use beam_scene::nonlinear::{Beam, Fit, SFace};

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
        fit.directions().map(Some)
    }
}

/// Unit directions of `beam`'s rays through the vertices of `f` (projection, 000 §5, extrapolated
/// past the beam's base): three Newton projections, which the tree keeps from one frame to the
/// next ([`super::trace::ThroughMemo`]).
pub(super) fn through(beam: &Beam, f: &SFace) -> Option<[Vec3; 3]> {
    let [a, b, c] = f.v.map(|v| beam.direction_through(v));
    Some([a?, b?, c?])
}
