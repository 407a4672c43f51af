//! # beam-cpu
//!
//! The CPU renderers of beam over the scenes of `beam-scene`: polygon beams (primary visibility,
//! exact soft shadows), nonlinear beams, glossy light volumes, and the ray-traced references. It is
//! a backend of `beam-render`: it implements that crate's renderer traits (its ray queries, the
//! nonlinear method's `BeamRenderer`) and renders with the host side it shares with beam-gpu, under
//! `beam-render`'s options.
//!
//! - [`render`]: polygon-beam and ray-traced images (001), the renderer and its shading.
//! - [`overdraw`]: the bounding-triangle overdraw experiment of 000 Fig. 7.
//! - [`glossy`]: glossy light volumes and caustics from point and area lights (002).
//! - [`nonlinear`]: the CPU's nonlinear beam renderer (000), `CpuBeams`, which the frame driver of
//!   `beam-render` runs.
//! - [`error`]: what a render or a comparison can fail with ([`RenderError`]).
//!
//! Exact soft shadows of the built-in Cornell box, 64×48, by polygon beams:
//!
//! ```
//! use beam_cpu::render::render;
//! use beam_render::options::RenderOptions;
//!
//! let scene = beam_cpu::beam_scene::scene::builtin("cornell").unwrap();
//! let (image, stats) = render(&scene, &RenderOptions::exact(64, 48), || {});
//! assert_eq!(image.pixels.len(), 64 * 48);
//! assert!(stats.shadow_beams > 0);
//! // image.save_png("cornell.png".as_ref()) writes it (atomically).
//! ```
//!
//! `cargo run --release -p beam-cpu --example soft_shadows` builds a scene in code instead.

pub mod error;
pub mod glossy;
pub mod nonlinear;
pub mod overdraw;
pub mod render;

pub use beam_math;
pub use beam_scene;
pub use error::RenderError;

/// The README's library example, compiled as a doctest so that it stays true.
#[doc = include_str!("../../README.md")]
#[cfg(doctest)]
pub struct ReadmeExample;
