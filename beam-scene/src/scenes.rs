//! Where the shared test scenes live: `$BEAM_SCENES`, else `../shared/scenes` from the working
//! directory, else `../shared/scenes` beside this workspace. Absent scenes are not an error: callers
//! skip with [`scenes_dir`]'s reason.

use std::path::{Path, PathBuf};

/// The scenes folder, or the reason it was not found.
pub fn scenes_dir() -> Result<PathBuf, String> {
    if let Some(dir) = std::env::var_os("BEAM_SCENES") {
        let dir = PathBuf::from(dir);
        return if dir.is_dir() { Ok(dir) } else { Err(format!("BEAM_SCENES={} is not a folder", dir.display())) };
    }
    let candidates =
        [PathBuf::from("../shared/scenes"), Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes")];
    candidates
        .into_iter()
        .find(|d| d.is_dir())
        .ok_or_else(|| "no scenes: set BEAM_SCENES or place the shared scenes at ../shared/scenes".to_string())
}

/// Every `.obj` file one level below the scenes folder, sorted.
pub fn shared_meshes() -> Result<Vec<PathBuf>, String> {
    let dir = scenes_dir()?;
    let mut out = Vec::new();
    for entry in std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))? {
        let sub = entry.map_err(|e| e.to_string())?.path();
        if sub.is_dir() {
            for f in std::fs::read_dir(&sub).map_err(|e| format!("{}: {e}", sub.display()))? {
                let f = f.map_err(|e| e.to_string())?.path();
                if f.extension().is_some_and(|e| e == "obj") {
                    out.push(f);
                }
            }
        }
    }
    out.sort();
    Ok(out)
}
