//! Reading input files safely: each input is read once, through one bounded reader, and only if it
//! is a regular file (a FIFO would block, `/dev/zero` never ends); paths a scene file names stay
//! inside the scene's folder unless the user allows otherwise; quoted lines are clipped.

use crate::error::SceneError;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

pub use crate::text::{QUOTE_CHARS, clip, quote, shown, visible};

/// Largest OBJ file read (1 GiB).
pub const MAX_MESH_BYTES: u64 = 1 << 30;
/// Largest TOML scene file read (4 MiB).
pub const MAX_SCENE_BYTES: u64 = 4 << 20;

/// The whole content of the regular file at `path`, read once, refused when it is larger than
/// `limit` bytes or is not a regular file (FIFO, device, folder). Errors name `path`.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, SceneError> {
    let fail = |source| SceneError::Read { path: path.to_path_buf(), source };
    let not_regular =
        |meta: &std::fs::Metadata| SceneError::NotRegularFile { path: path.to_path_buf(), kind: kind(meta) };
    // Check before opening: opening a FIFO for reading blocks until a writer appears.
    let meta = std::fs::metadata(path).map_err(fail)?;
    if !meta.is_file() {
        return Err(not_regular(&meta));
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    non_blocking(&mut options);
    let file = options.open(path).map_err(fail)?;
    // Check the opened handle too: the path may have been replaced since.
    let meta = file.metadata().map_err(fail)?;
    if !meta.is_file() {
        return Err(not_regular(&meta));
    }
    let too_big = || SceneError::TooLarge { path: path.to_path_buf(), limit };
    if meta.len() > limit {
        return Err(too_big());
    }
    let mut data = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1).read_to_end(&mut data).map_err(fail)?;
    if data.len() as u64 > limit {
        return Err(too_big());
    }
    Ok(data)
}

/// Open without blocking where the platform has `O_NONBLOCK` (no effect on regular files; a FIFO
/// swapped in after the metadata check then fails the handle check instead of hanging).
#[cfg(unix)]
fn non_blocking(options: &mut std::fs::OpenOptions) {
    use std::os::unix::fs::OpenOptionsExt;
    #[cfg(any(target_os = "linux", target_os = "android"))]
    options.custom_flags(0o4000);
    #[cfg(any(target_os = "macos", target_os = "ios", target_os = "freebsd", target_os = "openbsd"))]
    options.custom_flags(0x4);
    let _ = options;
}

#[cfg(not(unix))]
fn non_blocking(_: &mut std::fs::OpenOptions) {}

/// What kind of file `meta` describes, in words.
pub(crate) fn kind(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() { "a folder" } else { "not a plain file" }
}

/// Whether `name` ends in `.ext`, ignoring case (`CUBE.OBJ` is an `obj`).
#[must_use]
pub fn has_extension(name: &Path, ext: &str) -> bool {
    name.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// Where a file named in a scene file lies: `name` resolved against the scene's folder `dir`.
/// Unless `allow_outside`, the file (symlinks resolved) must lie inside `dir`; the second value
/// says whether it does (lines of files outside are not quoted in errors).
pub fn resolve_inside(dir: &Path, name: &str, allow_outside: bool) -> Result<(PathBuf, bool), SceneError> {
    if name.len() > 4096 || name.contains('\0') {
        return Err(SceneError::NotAFileName { name: name.to_string() });
    }
    let joined = dir.join(name);
    let outside =
        |resolved: bool| SceneError::OutsideFolder { name: name.to_string(), dir: dir.to_path_buf(), resolved };
    let root = dir.canonicalize().map_err(|source| SceneError::Folder { path: dir.to_path_buf(), source })?;
    match joined.canonicalize() {
        Ok(real) => {
            let inside = real.starts_with(&root);
            if !inside && !allow_outside {
                return Err(outside(true));
            }
            Ok((joined, inside))
        }
        // A missing file: say so only when its name stays inside the folder.
        Err(source) => {
            if !allow_outside && !lexically_inside(name) {
                return Err(outside(false));
            }
            Err(SceneError::Read { path: joined, source })
        }
    }
}

/// Whether the relative path `name` stays below its base folder without following links
/// (no root, no prefix, never more `..` than folders).
fn lexically_inside(name: &str) -> bool {
    let mut depth = 0i64;
    for c in Path::new(name).components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir => {
                depth -= 1;
                if depth < 0 {
                    return false;
                }
            }
            Component::RootDir | Component::Prefix(_) => return false,
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lexical_containment() {
        assert!(lexically_inside("a/b.obj"));
        assert!(lexically_inside("a/../b.obj"));
        assert!(!lexically_inside("../b.obj"));
        assert!(!lexically_inside("/etc/passwd"));
        assert!(!lexically_inside("a/../../b.obj"));
    }

    #[test]
    fn refuses_what_is_not_a_regular_file_and_what_is_too_big() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_bounded(dir.path(), 10).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        let p = dir.path().join("f");
        std::fs::write(&p, "12345").unwrap();
        assert_eq!(read_bounded(&p, 5).unwrap(), b"12345");
        assert!(read_bounded(&p, 4).unwrap_err().to_string().contains("larger than the 4 bytes limit"));
    }
}
