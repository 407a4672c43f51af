//! # beam-scene
//!
//! Scene data and its I/O, and nothing that renders: scenes (TOML files, glTF 2.0, bare OBJ, built-ins)
//! with their materials, lights, camera and BVH, the meshes they are made of, bounded reads of the
//! user's files and atomic writes of outputs. The renderer's traits, options and host-side methods
//! are `beam-render`'s, over this crate; `beam-cpu` and `beam-gpu` are its backends.
//!
//! - [`scene`]: scenes (TOML files, glTF 2.0, bare OBJ, built-ins): materials, lights, camera, BVHs.
//! - [`mesh`]: OBJ loading and procedural meshes; [`scenes`]: where the shared scenes are.
//! - [`io`]: atomic output files; [`read`]: bounded reads of input files; [`error`]: their errors
//!   ([`SceneError`], [`FaceError`]).
//! - [`region`]: pixel rectangles of a frame (a render farm's tiles); [`text`]: how messages show
//!   the user's text (clipped, quoted).
//!
//! ```
//! // The built-in Cornell box; `scene::load` also takes the path of a TOML, OBJ or glTF file.
//! let scene = beam_scene::scene::builtin("cornell").unwrap();
//! assert!(!scene.triangles.is_empty() && !scene.lights.is_empty());
//! let (w, h) = (scene.camera.width, scene.camera.height);
//! assert!(w > 0 && h > 0);
//! ```

pub mod error;
pub mod io;
pub mod mesh;
pub mod read;
pub mod region;
pub mod scene;
pub mod scenes;
pub mod text;

pub use beam_math;
pub use error::{FaceError, SceneError};
