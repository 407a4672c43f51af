//! Nonlinear beam tracing mathematics (000 §4–6, Appendices A and B): S^n beam parameterization,
//! affine and threshold planes, transfer, projection, extremal directions, maximum offsets, the
//! inside-beam test, bounding triangles (Algorithms 3 and 4, bump-map eq. 5) and bounding cones.

mod affine;
mod beam;
mod bounding_cone;
mod bounding_triangle;
mod bump;
mod extremal;
mod inside;
mod offsets;
mod parameterization;
mod projection;
mod threshold;

pub use affine::transfer;
pub use beam::{MIN_ELEVATION, NonlinearBeam, heights};
pub use bounding_cone::MIN_CONE_ANGLE;
pub use bounding_triangle::{BeamBounds, BoundingCase, BoundingTriangle, enclosing_triangle, relative_coordinates};
pub use bump::{BumpBeam, perturb};
pub use parameterization::{Interpolant, MAX_COEFFICIENTS, MAX_DEGREE, Patch, S1, S3, indices, multinomial};
pub use projection::{BARY_TOLERANCE, NEWTON_STEPS, Polish, Projection, Projections};
pub use threshold::ThresholdPlane;
