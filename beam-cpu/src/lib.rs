//! # beam-cpu
//!
//! Host side of beam: experiments and, as the rendering issues land, scenes, cameras, materials,
//! lights and the CPU renderers.
//!
//! - [`overdraw`]: the bounding-triangle overdraw experiment of 000 Fig. 7.
//! - [`glossy`]: glossy light volumes and caustics from point and area lights (002).
//! - [`io`]: atomic output files; [`read`]: bounded reads of input files.
//! - [`mesh`]: OBJ loading and procedural meshes; [`scenes`]: where the shared scenes are.
//! - [`nonlinear`]: nonlinear beam tracing of curved mirrors (000).
//! - [`scene`]: scenes (TOML files, bare OBJ, built-ins): materials, lights, camera, BVHs.

pub mod glossy;
pub mod io;
pub mod mesh;
pub mod nonlinear;
pub mod overdraw;
pub mod read;
pub mod render;
pub mod scene;
pub mod scenes;

pub use beam_math;
