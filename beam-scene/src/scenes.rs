//! Where the shared test scenes live: `$BEAM_SCENES`, else `../shared/scenes` from the working
//! directory, else `../shared/scenes` beside this workspace. Absent scenes are not an error: callers
//! skip with [`scenes_dir`]'s reason.

use crate::error::SceneError;
use std::path::{Path, PathBuf};

/// The scenes folder, or the reason it was not found.
pub fn scenes_dir() -> Result<PathBuf, SceneError> {
    if let Some(dir) = std::env::var_os("BEAM_SCENES") {
        let dir = PathBuf::from(dir);
        return if dir.is_dir() { Ok(dir) } else { Err(SceneError::NoScenes { beam_scenes: Some(dir) }) };
    }
    let candidates =
        [PathBuf::from("../shared/scenes"), Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes")];
    candidates.into_iter().find(|d| d.is_dir()).ok_or(SceneError::NoScenes { beam_scenes: None })
}

/// Every `.obj` file one level below the scenes folder, sorted.
pub fn shared_meshes() -> Result<Vec<PathBuf>, SceneError> {
    let dir = scenes_dir()?;
    let folder = |path: &Path| {
        let path = path.to_path_buf();
        move |source| SceneError::Folder { path, source }
    };
    let mut out = Vec::new();
    for entry in std::fs::read_dir(&dir).map_err(folder(&dir))? {
        let sub = entry.map_err(folder(&dir))?.path();
        if sub.is_dir() {
            for f in std::fs::read_dir(&sub).map_err(folder(&sub))? {
                let f = f.map_err(folder(&sub))?.path();
                if f.extension().is_some_and(|e| e == "obj") {
                    out.push(f);
                }
            }
        }
    }
    out.sort();
    Ok(out)
}
