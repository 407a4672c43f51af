//! The errors of a glTF file: at an element of it, or of the file as a whole.

use crate::error::SceneError;
use std::fmt::Display;
use std::path::Path;

/// An error of the glTF file `path` at `element` (`mesh 2 primitive 0`, `node 3`).
pub(super) fn error(path: &Path, element: impl Display, message: impl Display) -> SceneError {
    SceneError::Gltf { path: path.to_path_buf(), element: Some(element.to_string()), message: message.to_string() }
}

/// An error of the glTF file `path` as a whole.
pub(super) fn file_error(path: &Path, message: impl Display) -> SceneError {
    SceneError::Gltf { path: path.to_path_buf(), element: None, message: message.to_string() }
}
