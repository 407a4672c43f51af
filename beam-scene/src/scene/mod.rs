//! Scenes: triangles with materials, lights and a camera, from a TOML scene file, a glTF 2.0 file,
//! a bare OBJ file or a built-in name.

mod builtin;
mod bump;
mod camera;
mod camera_path;
mod check;
mod cut_out_triangles;
mod defaults;
mod environment;
mod environment_file;
mod file;
pub mod foliage;
mod format;
pub mod framing;
mod gltf;
mod image_file;
pub mod interior;
mod light;
pub mod light_volumes;
mod load_options;
mod material;
mod merge_emitters;
mod model;
pub(crate) mod names;
mod normals;
mod obj_materials;
mod ray_queries;
pub mod showcase;
mod smesh_file;
mod smesh_plan;
pub mod suite;
pub mod surface;
pub mod texture;

pub use builtin::{builtin, builtin_with_smesh};
pub use camera::{Camera, CameraFrame};
pub use camera_path::{CameraKey, CameraPath};
pub use cut_out_triangles::CutOutTriangles;
pub use environment::{
    Environment, EnvironmentMap, MAX_ENVIRONMENT_BYTES, MAX_ENVIRONMENT_SIDE, MAX_ENVIRONMENT_TEXELS,
};
pub use file::{load, load_file, load_file_with, load_with};
pub use light::Light;
pub use load_options::LoadOptions;
pub use material::{Bump, Material};
pub use model::{Notice, Scene, SceneStats};
pub use names::{BUILTIN, PROCEDURAL};
pub use ray_queries::{MAX_CUT_OUT_LAYERS, past_hit};
pub use smesh_plan::{MAX_SMESH_FACES, SMeshPlan, SMeshSource, Simplify};
