//! # beam-scene
//!
//! What both backends render, and nothing that renders: scenes (TOML files, bare OBJ, built-ins)
//! with their materials, lights, camera and BVH, the meshes they are made of, bounded reads of the
//! user's files and atomic writes of outputs. `beam-cpu` and `beam-gpu` both build on it.
//!
//! - [`scene`]: scenes (TOML files, bare OBJ, built-ins): materials, lights, camera, BVHs.
//! - [`mesh`]: OBJ loading and procedural meshes; [`scenes`]: where the shared scenes are.
//! - [`io`]: atomic output files; [`read`]: bounded reads of input files.

pub mod io;
pub mod mesh;
pub mod read;
pub mod scene;
pub mod scenes;

pub use beam_math;
