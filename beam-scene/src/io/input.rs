//! Opening an input image: only a regular file, with errors that name it.

use crate::error::SceneError;
use std::fs::File;
use std::path::Path;

/// `path` opened for reading, after refusing what is not a regular file (a FIFO would block, a
/// device never end). Errors name the path.
pub(super) fn regular_file(path: &Path) -> Result<File, SceneError> {
    let fail = |source| SceneError::Read { path: path.to_path_buf(), source };
    let meta = std::fs::metadata(path).map_err(fail)?;
    if !meta.is_file() {
        return Err(SceneError::NotRegularFile { path: path.to_path_buf(), kind: crate::read::kind(&meta) });
    }
    File::open(path).map_err(fail)
}

/// An [`SceneError::Image`] error of the file `path`.
pub(super) fn image_error(path: &Path, message: impl std::fmt::Display) -> SceneError {
    SceneError::Image { path: Some(path.to_path_buf()), message: message.to_string() }
}
