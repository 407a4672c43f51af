//! # beam-scene
//!
//! What both backends render and share, and nothing that renders: scenes (TOML files, glTF 2.0, bare OBJ,
//! built-ins) with their materials, lights, camera and BVH, the meshes they are made of, bounded reads of the
//! user's files and atomic writes of outputs. `beam-cpu` and `beam-gpu` both build on it.
//!
//! - [`scene`]: scenes (TOML files, glTF 2.0, bare OBJ, built-ins): materials, lights, camera, BVHs.
//! - [`mesh`]: OBJ loading and procedural meshes; [`scenes`]: where the shared scenes are.
//! - [`io`]: atomic output files; [`read`]: bounded reads of input files; [`error`]: their errors
//!   ([`SceneError`]) and the backends' ([`BackendError`]).
//! - [`region`]: pixel rectangles of a frame (a render farm's tiles).
//! - [`cpu_clock`]: CPU time of the calling thread and of rayon's workers (benchmarks, host time
//!   beside a software GPU).
//! - [`queries`]: ray queries, one vocabulary for all; [`options`]: render settings; [`specular`]: the mirror and glass bounce; [`tolerance`]: the
//!   offsets both backends use; [`irradiance_map`]: caustic irradiance on receiving planes.
//! - [`nonlinear`], [`glossy`]: the host side of the nonlinear beam tree (000) and of the glossy
//!   light volumes (002) that every backend shares.
//!
//! ```
//! // The built-in Cornell box; `scene::load` also takes the path of a TOML, OBJ or glTF file.
//! let scene = beam_scene::scene::builtin("cornell").unwrap();
//! assert!(!scene.triangles.is_empty() && !scene.lights.is_empty());
//! let (w, h) = (scene.camera.width, scene.camera.height);
//! assert!(w > 0 && h > 0);
//! ```

pub mod cpu_clock;
pub mod error;
pub mod glossy;
pub mod io;
pub mod irradiance_map;
pub mod memo;
pub mod mesh;
pub mod nonlinear;
pub mod options;
pub mod parallel;
pub mod queries;
pub mod read;
pub mod region;
pub mod scene;
pub mod scenes;
pub mod specular;
pub mod text;
pub mod tolerance;

pub use beam_math;
pub use error::{BackendError, FaceError, SceneError};
