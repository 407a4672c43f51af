//! Output files written atomically: to a temporary file in the destination folder, then renamed,
//! so a failed or interrupted run never leaves a half-written image or table behind.
//!
//! The policy, for every file `beam` writes:
//! - the target must be absent or an existing, writable regular file: a symbolic link, FIFO, device
//!   node, socket or directory is refused, never followed or replaced, and so is a read-only file;
//! - its folder must exist and be writable ([`check_output`] says so before a long run starts);
//! - the bytes go to `.NAME.beam-tmp-XXXXXXXXXXXXXXXX` beside it, are synced, and the temporary is
//!   renamed over the target; several files written together ([`write_atomic_all`]) are all written
//!   and synced before the first is renamed, so a failure to write one replaces none;
//! - a new file gets the usual mode (`0o666` less the umask); a replaced file keeps its mode;
//! - on every error the temporary is removed. Only a process killed outright (a signal, no handler
//!   is installed) may leave a `.NAME.beam-tmp-*` file, which is safe to delete.
//!
//! Errors name the user's path, never the temporary's.

use std::fs::{File, OpenOptions};
use std::hash::{BuildHasher, Hasher};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The marker of temporary names: `.NAME.beam-tmp-XXXXXXXXXXXXXXXX`.
pub const TEMP_MARKER: &str = ".beam-tmp-";

/// `path`'s folder (`.` for a bare name) and file name; an error for a path that names no file.
fn split(path: &Path) -> Result<(&Path, &std::ffi::OsStr), String> {
    let name = path.file_name().ok_or_else(|| format!("{}: names no file", path.display()))?;
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    Ok((dir, name))
}

/// The target's metadata (not following a symbolic link) when it exists, after refusing what may not
/// be replaced: anything but a regular file, and a read-only or unwritable file.
fn check_target(path: &Path) -> Result<Option<std::fs::Metadata>, String> {
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("{}: {e}", path.display())),
    };
    let ft = meta.file_type();
    let kind = if ft.is_symlink() {
        "a symbolic link"
    } else if ft.is_dir() {
        "a directory"
    } else if ft.is_file() {
        ""
    } else {
        special_kind(&ft)
    };
    if !kind.is_empty() {
        return Err(format!("{}: is {kind}, not a regular file; refusing to replace it", path.display()));
    }
    if meta.permissions().readonly() {
        return Err(format!("{}: is read-only; refusing to replace it", path.display()));
    }
    // Open for writing without truncating: the mode bits may allow it while ownership does not.
    OpenOptions::new().write(true).open(path).map_err(|e| format!("{}: not writable: {e}", path.display()))?;
    Ok(Some(meta))
}

#[cfg(unix)]
fn special_kind(ft: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_fifo() {
        "a FIFO"
    } else if ft.is_char_device() || ft.is_block_device() {
        "a device node"
    } else if ft.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "a special file"
}

/// A temporary file beside its target, removed on drop unless renamed.
struct Temp {
    path: PathBuf,
    file: File,
    renamed: bool,
}

impl Temp {
    /// Create `.NAME.beam-tmp-XXXX` in `dir`, with the default mode (`0o666` less the umask).
    fn create(dir: &Path, name: &std::ffi::OsStr) -> std::io::Result<Self> {
        let mut last = None;
        for _ in 0..16 {
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_u32(std::process::id());
            let mut tmp_name = std::ffi::OsString::from(".");
            tmp_name.push(name);
            tmp_name.push(format!("{TEMP_MARKER}{:016x}", h.finish()));
            let path = dir.join(tmp_name);
            match OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(file) => return Ok(Self { path, file, renamed: false }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
                Err(e) => return Err(e),
            }
        }
        Err(last.unwrap_or_else(|| std::io::Error::other("no free temporary name")))
    }
}

impl Drop for Temp {
    fn drop(&mut self) {
        if !self.renamed {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Check, before any work, that `path` can be written: its folder exists and takes new files, and
/// the target is absent or a writable regular file. Errors name `path`.
pub fn check_output(path: &Path) -> Result<(), String> {
    let (dir, name) = split(path)?;
    let fail = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(fail(&format!("{} is not a directory", dir.display()))),
        Err(e) => return Err(fail(&format!("folder {}: {e}", dir.display()))),
    }
    check_target(path)?;
    // The folder's mode bits do not tell (root, ACLs, read-only mounts): try a temporary file.
    Temp::create(dir, name).map_err(|e| fail(&format!("cannot create a file in {}: {e}", dir.display())))?;
    Ok(())
}

/// True when `a` and `b` name the same file: the same folder (after resolving links) and name, or,
/// when both exist, the same file on disk (hard links).
#[must_use]
pub fn same_file(a: &Path, b: &Path) -> bool {
    let resolve = |p: &Path| {
        let (dir, name) = split(p).ok()?;
        Some(std::fs::canonicalize(dir).ok()?.join(name))
    };
    if a == b {
        return true;
    }
    if let (Some(x), Some(y)) = (resolve(a), resolve(b)) {
        if x == y {
            return true;
        }
    }
    #[cfg(unix)]
    if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return (x.dev(), x.ino()) == (y.dev(), y.ino());
    }
    false
}

/// Write each `(path, bytes)` atomically, as a group: every temporary is written and synced before
/// the first rename, so an error while writing any of them replaces none. Errors name the path.
pub fn write_atomic_all(files: &[(&Path, &[u8])]) -> Result<(), String> {
    for (i, (a, _)) in files.iter().enumerate() {
        if files[..i].iter().any(|(b, _)| same_file(a, b)) {
            return Err(format!("{}: named twice as an output", a.display()));
        }
    }
    let mut temps = Vec::with_capacity(files.len());
    for &(path, bytes) in files {
        let fail = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
        let (dir, name) = split(path)?;
        let old = check_target(path)?;
        let mut tmp = Temp::create(dir, name).map_err(|e| fail(&e))?;
        let file = &mut tmp.file;
        file.write_all(bytes).map_err(|e| fail(&e))?;
        if let Some(old) = old {
            // A replaced file keeps its mode.
            file.set_permissions(old.permissions()).map_err(|e| fail(&e))?;
        }
        file.sync_all().map_err(|e| fail(&e))?;
        temps.push((path, dir, tmp));
    }
    for (path, dir, tmp) in &mut temps {
        let (path, dir): (&Path, &Path) = (path, dir);
        // Checked again: the target may have changed while the temporaries were written.
        check_target(path)?;
        std::fs::rename(&tmp.path, path).map_err(|e| format!("{}: {e}", path.display()))?;
        tmp.renamed = true;
        // Make the rename durable (best effort: not every platform opens folders).
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

/// Write `bytes` to `path` atomically. Errors name the path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    write_atomic_all(&[(path, bytes)])
}

/// Encode an 8-bit RGB image as PNG bytes.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    let encoder = image::codecs::png::PngEncoder::new(&mut bytes);
    image::ImageEncoder::write_image(encoder, rgb, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// Encode an 8-bit RGB image as PNG and write it atomically.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), String> {
    let bytes = encode_png(width, height, rgb).map_err(|e| format!("{}: {e}", path.display()))?;
    write_atomic(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(dir: &Path) -> usize {
        std::fs::read_dir(dir).unwrap().count()
    }

    #[test]
    fn writes_and_replaces() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(entries(dir.path()), 1, "no temporary file left behind");
        let err = write_atomic(&dir.path().join("missing/b.txt"), b"x").unwrap_err();
        assert!(err.contains("missing/b.txt") && !err.contains(TEMP_MARKER), "{err}");
        assert!(check_output(&dir.path().join("missing/b.txt")).is_err());
        check_output(&p).unwrap();
        assert_eq!(entries(dir.path()), 1, "the check leaves nothing behind");
    }

    #[cfg(unix)]
    #[test]
    fn modes_links_and_special_files() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        // A replaced file keeps its mode; a read-only one is refused.
        let p = dir.path().join("a.png");
        std::fs::write(&p, b"old").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(mode(&p), 0o600);
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o444)).unwrap();
        let err = write_atomic(&p, b"x").unwrap_err();
        assert!(err.contains("read-only") && std::fs::read(&p).unwrap() == b"new", "{err}");
        // A symbolic link is refused, and neither it nor its target changes.
        let target = dir.path().join("target");
        std::fs::write(&target, b"keep").unwrap();
        let link = dir.path().join("link.png");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let err = write_atomic(&link, b"x").unwrap_err();
        assert!(err.contains("symbolic link"), "{err}");
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"keep");
        assert!(write_atomic(Path::new("/dev/null"), b"x").unwrap_err().contains("device node"));
        assert!(write_atomic(dir.path(), b"x").unwrap_err().contains("directory"));
        // Two outputs: a failure on the second replaces neither.
        let q = dir.path().join("b.json");
        std::fs::write(&q, b"old").unwrap();
        let err = write_atomic_all(&[(&q, b"new"), (&dir.path().join("no/such"), b"x")]).unwrap_err();
        assert!(err.contains("no/such"), "{err}");
        assert_eq!(std::fs::read(&q).unwrap(), b"old");
        assert!(write_atomic_all(&[(&q, b"1"), (&dir.path().join(".").join("b.json"), b"2")]).is_err());
        let leftovers = std::fs::read_dir(dir.path())
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().contains(TEMP_MARKER))
            .count();
        assert_eq!(leftovers, 0);
    }
}
