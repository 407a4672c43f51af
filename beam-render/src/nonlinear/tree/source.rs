//! Where the light arriving at an S-mesh face comes from, and its directions at the face's
//! vertices (000 §7.2).

use crate::nonlinear::beam_tree::Beam;
use crate::nonlinear::face::SFace;
use beam_math::glam::Vec3;

/// Unit directions of the light from the eye at the vertices of `f`; `None` where the eye is on
/// one of them. (From a parent beam they are its texel rays' fit, [`Fit::directions`], else its
/// rays through the vertices, [`through`].)
///
/// [`Fit::directions`]: crate::nonlinear::Fit::directions
pub(crate) fn from_eye(eye: Vec3, f: &SFace) -> Option<[Vec3; 3]> {
    let [a, b, c] = f.v.map(|v| (v - eye).try_normalize());
    Some([a?, b?, c?])
}

/// Unit directions of `beam`'s rays through the vertices of `f` (projection, 000 §5, extrapolated
/// past the beam's base): three Newton projections, which the tree keeps from one frame to the
/// next ([`super::tree::ThroughMemo`]).
pub(crate) fn through(beam: &Beam, f: &SFace) -> Option<[Vec3; 3]> {
    let [a, b, c] = f.v.map(|v| beam.direction_through(v));
    Some([a?, b?, c?])
}
