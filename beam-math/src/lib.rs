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
//!
//! The exact soft-shadow term of 001 in a few lines: split the beam from a point to a square
//! light by an occluder and measure what misses it. This triangle, half way up, hides the
//! light's half `x < 0`:
//!
//! ```
//! use beam_math::glam::Vec3;
//! use beam_math::polybeam::{BeamFrame, PolyBeam};
//! use beam_math::Triangle;
//!
//! let point = Vec3::ZERO;
//! let light = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)].map(|(x, z)| Vec3::new(x, 2.0, z));
//! let frame = BeamFrame::new(point, Vec3::new(0.0, 2.0, 0.0), Vec3::Y, Vec3::X).unwrap();
//! let beam = PolyBeam::new(frame, &light).unwrap();
//! let occluder = Triangle::new(Vec3::new(0.0, 1.0, -1.0), Vec3::new(0.0, 1.0, 1.0), Vec3::new(-1.0, 1.0, 0.0));
//! // Occluders count between the point (depth 0) and the light (depth 1); 1e-5 is the fuzzy tolerance.
//! let split = beam.split(&occluder, 0.0, 1.0, 1e-5).unwrap();
//! let visible = split.miss.area() / beam.area();
//! assert!((visible - 0.5).abs() < 1e-6);
//! ```
//!
//! `examples/cortex-m4f` in the repository runs the same on a Cortex-M4F (under QEMU in CI).

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
