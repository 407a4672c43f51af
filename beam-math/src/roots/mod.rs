//! Real roots of quadratics, cubics and quartics in `f64`, robust near double and triple roots.
//!
//! Cubics and quartics are solved by isolating roots between the critical points (the roots of the
//! derivative, found recursively): on each interval the polynomial is monotone, so a sign change
//! brackets exactly one root, which a safeguarded Newton–bisection iteration refines to full
//! precision. A critical point where the polynomial vanishes to within its rounding error is a
//! multiple root and is reported once. No closed-form cancellation, so no lost digits at double roots.

mod cubic;
mod poly;
mod quadratic;
mod quartic;

pub use cubic::cubic;
pub use poly::Roots;
pub use quadratic::quadratic;
pub use quartic::quartic;
