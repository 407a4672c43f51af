//! # beam-cpu
//!
//! The CPU renderers of beam over the scenes of `beam-scene`: polygon beams (primary visibility,
//! exact soft shadows), nonlinear beams, glossy light volumes, and the ray-traced references.
//!
//! - [`render`]: polygon-beam and ray-traced images (001), the renderer and its shading.
//! - [`overdraw`]: the bounding-triangle overdraw experiment of 000 Fig. 7.
//! - [`glossy`]: glossy light volumes and caustics from point and area lights (002).
//! - [`nonlinear`]: nonlinear beam tracing of curved mirrors (000).

pub mod glossy;
pub mod nonlinear;
mod ordered;
pub mod overdraw;
pub mod render;

pub use beam_math;
pub use beam_scene;
