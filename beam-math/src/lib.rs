//! # beam-math
//!
//! The `no_std`, allocation-free geometry core of **beam**: everything a shader or a
//! microcontroller could run. Modules follow the four papers of the specification:
//!
//! - [`collide`]: the collision and culling routines of 004 App. A and the cone–sphere test of
//!   000 App. A.
//! - [`roots`]: real roots of quadratics, cubics and quartics.
//! - [`nonlinear`]: nonlinear beams (000 §4–6, Apps. A–B): S^n parameterization, projection,
//!   threshold plane, bounding triangles and cones.
//! - [`polybeam`]: polygon beams split exactly by triangles (001 §3).
//! - [`glossy`]: flux planes and triangles and Gaussian volumes (002 §3–4).
//! - [`heuristics`]: surface and projected areas for BVH cost models (004).
//!
//! Features: `std` (default) or `libm` select where float functions come from; one must be on.
//! `cargo build -p beam-math --no-default-features --features libm --target thumbv7em-none-eabihf`
//! builds it for a Cortex-M4F.

#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("beam-math needs the `std` or the `libm` feature for its float functions");

pub mod collide;
pub mod float;
pub mod glossy;
pub mod heuristics;
pub mod nonlinear;
pub mod polybeam;
pub mod roots;
pub mod shapes;

pub use glam;
pub use shapes::{Aabb, Plane, Ray, Triangle};
