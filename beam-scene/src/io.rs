//! Output files written atomically: to a temporary file in the destination folder, then renamed,
//! so a failed or interrupted run never leaves a half-written image or table behind; and the image
//! formats a render is written in: PNG (8-bit sRGB) and OpenEXR (linear `f32`), each able to say
//! where a render farm's tile sits in its frame ([`encode_png_placed`], [`encode_exr`]).
//!
//! The policy, for every file `beam` writes:
//! - the target must be absent or an existing, writable regular file: a symbolic link, FIFO, device
//!   node, socket or directory is refused, never followed or replaced, and so is a read-only file;
//! - its folder must exist and be writable ([`check_output`] says so before a long run starts);
//! - the bytes go to `.NAME.beam-tmp-XXXXXXXXXXXXXXXX` beside it, are synced, and the temporary is
//!   renamed over the target, then the folder is synced (best effort); each file on its own is
//!   therefore always either wholly old or wholly new, never a mix or a prefix;
//! - a new file gets the usual mode (`0o666` less the umask); a replaced file keeps its mode;
//! - on every error the temporaries are removed. Errors name the user's path, never a temporary's
//!   (but for the one case below where a backup holds a file's old content).
//!
//! # Several files together
//!
//! [`write_atomic_all`] (a render's `--out` and `--stats`) writes them as nearly all-or-nothing as
//! POSIX allows, which has no rename of two files at once:
//! 1. every temporary is written and synced before anything is renamed: an error here changes no
//!    target;
//! 2. every existing target but the last is hard-linked aside to a `.NAME.beam-tmp-*` name (copied
//!    and synced where the file system has no hard links): an error here changes no target;
//! 3. the temporaries are renamed in order; if one rename fails, the targets already replaced are
//!    put back, each renamed back from its link (the very same file: content, mode, owner, inode)
//!    or removed when it did not exist before, and the error names the file that failed. Only if
//!    putting one back fails too (a disk gone read-only, say) does the error also name the
//!    `.NAME.beam-tmp-*` link that keeps its old content, which is then left in place.
//!
//! What is not guaranteed: another process reading the targets while step 3 runs (a few system
//! calls) may see some new and some old; and a crash, a power cut or `SIGKILL` during step 3
//! leaves the earlier targets new and the later ones old, with `.NAME.beam-tmp-*` files beside them.
//! A power cut shortly after a successful write may also lose some of the renames (the folder is
//! synced after them, but the file system decides what reaches the disk first).
//!
//! # Signals
//!
//! The library installs no signal handler. Every temporary and backup it creates is registered
//! while it exists, and [`remove_temporaries`] removes all of them and makes later writes fail; a
//! program calls it when a signal asks it to stop (the `beam` binary does, for `SIGINT`, `SIGTERM`
//! and `SIGHUP`, then exits with status 128 + the signal's number). It waits for a group of renames
//! in progress (step 3) to finish or be rolled back, so a caught signal leaves every target of a
//! group either as it was or new, and no `.NAME.beam-tmp-*` file. `SIGKILL` cannot be caught: a
//! process killed by it (or by a crash or power cut) may still leave `.NAME.beam-tmp-*` files, which
//! are safe to delete.

use crate::error::{SceneError, Unrestored};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::Path;

mod exr_file;
mod input;
mod png_file;
mod temporaries;

pub(crate) use exr_file::read_rgb;
pub use exr_file::{encode_exr, read_exr, read_exr_placement};
use png_file::png_bytes;
pub use png_file::{REGION_KEY, encode_png, encode_png_placed, read_png_placed, read_png_placement};
pub use temporaries::{TEMP_MARKER, remove_temporaries};
use temporaries::{Temp, interrupted, registry};

/// `path`'s folder (`.` for a bare name) and file name; an error for a path that names no file.
fn split(path: &Path) -> Result<(&Path, &std::ffi::OsStr), SceneError> {
    let name = path.file_name().ok_or_else(|| refused(path, "names no file"))?;
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    Ok((dir, name))
}

/// `path` may not be written, for `reason`.
fn refused(path: &Path, reason: impl Into<String>) -> SceneError {
    SceneError::Refused { path: path.to_path_buf(), reason: reason.into() }
}

/// Writing `path` failed at step `context` (none: the message needs none) with `source`.
fn write_error(path: &Path, context: Option<String>, source: std::io::Error) -> SceneError {
    SceneError::Write { path: path.to_path_buf(), context, source }
}

/// The target's metadata (not following a symbolic link) when it exists, after refusing what may not
/// be replaced: anything but a regular file, and a read-only or unwritable file.
fn check_target(path: &Path) -> Result<Option<std::fs::Metadata>, SceneError> {
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(write_error(path, None, e)),
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
        return Err(refused(path, format!("is {kind}, not a regular file; refusing to replace it")));
    }
    if meta.permissions().readonly() {
        return Err(refused(path, "is read-only; refusing to replace it"));
    }
    // Open for writing without truncating: the mode bits may allow it while ownership does not.
    OpenOptions::new().write(true).open(path).map_err(|e| write_error(path, Some("not writable".into()), e))?;
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

/// Check, before any work, that `path` can be written: its folder exists and takes new files, and
/// the target is absent or a writable regular file. Errors name `path`.
pub fn check_output(path: &Path) -> Result<(), SceneError> {
    let (dir, name) = split(path)?;
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(refused(path, format!("{} is not a directory", dir.display()))),
        Err(e) => return Err(write_error(path, Some(format!("folder {}", dir.display())), e)),
    }
    check_target(path)?;
    // The folder's mode bits do not tell (root, ACLs, read-only mounts): try a temporary file.
    Temp::create(dir, name)
        .map_err(|e| write_error(path, Some(format!("cannot create a file in {}", dir.display())), e))?;
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

/// Write each `(path, bytes)` atomically, as a group, as nearly all-or-nothing as POSIX allows
/// (the module's documentation says exactly what is guaranteed): every temporary is written and
/// synced, and every existing target but the last kept aside, before the first rename, and a failed
/// rename puts back the targets already replaced. Errors name the path.
pub fn write_atomic_all(files: &[(&Path, &[u8])]) -> Result<(), SceneError> {
    for (i, (a, _)) in files.iter().enumerate() {
        if files[..i].iter().any(|(b, _)| same_file(a, b)) {
            return Err(refused(a, "named twice as an output"));
        }
    }
    // 1. Write and sync every temporary.
    let mut temps = Vec::with_capacity(files.len());
    for &(path, bytes) in files {
        let fail = |e| write_error(path, None, e);
        let (dir, name) = split(path)?;
        let old = check_target(path)?;
        let (tmp, mut file) = Temp::create(dir, name).map_err(fail)?;
        // Pushed first, so that the temporary is removed on every error below.
        temps.push((path, dir, name, tmp));
        file.write_all(bytes).map_err(fail)?;
        if let Some(old) = old {
            // A replaced file keeps its mode.
            file.set_permissions(old.permissions()).map_err(fail)?;
        }
        file.sync_all().map_err(fail)?;
    }
    let mut backups: Vec<Option<Temp>> = Vec::with_capacity(temps.len());
    // From here to the end the registry stays locked, so that `remove_temporaries` (a signal)
    // waits for the renames to finish or be undone. Declared after `temps` and `backups`, it is
    // released first on every return, before the files still there are dropped (which locks it).
    let mut guard = registry();
    let reg = &mut *guard;
    if reg.closed {
        return Err(write_error(files[0].0, None, interrupted()));
    }
    // 2. Check the targets again (they may have changed while the temporaries were written), and
    // keep every existing one but the last aside, to put it back if a later rename fails.
    for (i, &(path, dir, name, _)) in temps.iter().enumerate() {
        let exists = check_target(path)?.is_some();
        let backup = if exists && i + 1 < temps.len() {
            let keep = Temp::backup(reg, dir, name, path);
            Some(keep.map_err(|e| write_error(path, Some("cannot keep the old file aside".into()), e))?)
        } else {
            None
        };
        backups.push(backup);
    }
    // 3. Rename, in order; on a failure, undo the renames done.
    for i in 0..temps.len() {
        #[cfg(test)]
        tests::before_rename(i);
        let path = temps[i].0;
        if let Err(source) = temps[i].3.rename(reg, path) {
            let mut unrestored = Vec::new();
            for j in (0..i).rev() {
                let target = temps[j].0;
                let undone = match &mut backups[j] {
                    Some(b) => b.rename(reg, target),
                    None => std::fs::remove_file(target),
                };
                if let Err(e) = undone {
                    let backup = backups[j].as_mut().map(|b| {
                        b.keep(reg);
                        b.path.clone()
                    });
                    unrestored.push(Unrestored { path: target.to_path_buf(), source: e, backup });
                }
            }
            sync_folders(&temps[..i]);
            for b in backups.iter_mut().flatten() {
                b.remove(reg);
            }
            return Err(SceneError::Rename { path: path.to_path_buf(), source, earlier: i, unrestored });
        }
    }
    sync_folders(&temps);
    for b in backups.iter_mut().flatten() {
        b.remove(reg);
    }
    Ok(())
}

/// Make renames in the folders of `temps` durable (best effort: not every platform opens folders).
fn sync_folders(temps: &[(&Path, &Path, &std::ffi::OsStr, Temp)]) {
    for (i, (_, dir, _, _)) in temps.iter().enumerate() {
        if temps[..i].iter().all(|(_, d, _, _)| d != dir) {
            if let Ok(d) = File::open(dir) {
                let _ = d.sync_all();
            }
        }
    }
}

/// Write `bytes` to `path` atomically. Errors name the path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    write_atomic_all(&[(path, bytes)])
}

/// Encode an 8-bit RGB image as PNG and write it atomically.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), SceneError> {
    let bytes =
        png_bytes(width, height, rgb).map_err(|source| SceneError::Png { path: Some(path.to_path_buf()), source })?;
    write_atomic(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    type Hook = Box<dyn FnMut(usize)>;

    thread_local! {
        /// Run by `write_atomic_all` on this thread just before its `i`-th rename.
        static BEFORE_RENAME: RefCell<Option<Hook>> = RefCell::new(None);
    }

    pub(super) fn before_rename(i: usize) {
        BEFORE_RENAME.with(|h| {
            if let Some(f) = h.borrow_mut().as_mut() {
                f(i);
            }
        });
    }

    /// `write_atomic_all(files)` with `hook` run before each rename.
    fn write_with_hook(files: &[(&Path, &[u8])], hook: impl FnMut(usize) + 'static) -> Result<(), String> {
        BEFORE_RENAME.with(|h| *h.borrow_mut() = Some(Box::new(hook)));
        let r = write_atomic_all(files).map_err(|e| e.to_string());
        BEFORE_RENAME.with(|h| *h.borrow_mut() = None);
        r
    }

    fn entries(dir: &Path) -> usize {
        std::fs::read_dir(dir).unwrap().count()
    }

    fn temporaries(dir: &Path) -> Vec<std::ffi::OsString> {
        let names = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name());
        names.filter(|n| n.to_string_lossy().contains(TEMP_MARKER)).collect()
    }

    /// Replace `path` (a file) by a non-empty directory: a rename over it fails, even as root.
    fn block(path: &Path) {
        let _ = std::fs::remove_file(path);
        std::fs::create_dir(path).unwrap();
        std::fs::write(path.join("inside"), b"x").unwrap();
    }

    /// `write_atomic_all` of new `stats` and `out`, where `out` becomes a directory after it was
    /// checked, before its rename: the error.
    fn write_pair_blocking_second(stats: &Path, out: &Path) -> String {
        let blocked = out.to_path_buf();
        write_with_hook(&[(stats, b"new stats"), (out, b"new image")], move |i| {
            if i == 1 {
                block(&blocked);
            }
        })
        .unwrap_err()
    }

    #[test]
    fn a_failed_second_rename_puts_the_first_back() {
        let dir = tempfile::tempdir().unwrap();
        let stats = dir.path().join("s.json");
        let out = dir.path().join("o.png");
        std::fs::write(&stats, b"old stats").unwrap();
        std::fs::write(&out, b"old image").unwrap();
        #[cfg(unix)]
        let inode = |p: &Path| std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(p).unwrap());
        #[cfg(unix)]
        let stats_inode = inode(&stats);
        let err = write_pair_blocking_second(&stats, &out);
        assert!(err.contains("o.png") && err.contains("put back as they were"), "{err}");
        assert!(!err.contains(TEMP_MARKER), "{err}");
        assert_eq!(std::fs::read(&stats).unwrap(), b"old stats");
        #[cfg(unix)]
        assert_eq!(inode(&stats), stats_inode, "the very same file is back");
        assert_eq!(temporaries(dir.path()), Vec::<std::ffi::OsString>::new());
        // A first target that did not exist is removed again.
        std::fs::remove_dir_all(&out).unwrap();
        std::fs::remove_file(&stats).unwrap();
        std::fs::write(&out, b"old image").unwrap();
        let err = write_pair_blocking_second(&stats, &out);
        assert!(err.contains("put back"), "{err}");
        assert!(!stats.exists());
        assert_eq!(temporaries(dir.path()), Vec::<std::ffi::OsString>::new());
        // Without a hook the same pair is written whole.
        std::fs::remove_dir_all(&out).unwrap();
        write_atomic_all(&[(&stats, b"new stats"), (&out, b"new image")]).unwrap();
        assert_eq!(std::fs::read(&stats).unwrap(), b"new stats");
        assert_eq!(std::fs::read(&out).unwrap(), b"new image");
        assert_eq!(entries(dir.path()), 2);
    }

    #[test]
    fn a_failed_put_back_names_the_backup() {
        let dir = tempfile::tempdir().unwrap();
        let stats = dir.path().join("s.json");
        let out = dir.path().join("o.png");
        std::fs::write(&stats, b"old stats").unwrap();
        std::fs::write(&out, b"old image").unwrap();
        let d = dir.path().to_path_buf();
        let err = write_with_hook(&[(&stats, b"new stats"), (&out, b"new image")], move |i| {
            if i == 1 {
                block(&d.join("o.png"));
                // The backup of s.json is the only temporary left; make putting it back fail too,
                // by making `s.json` a non-empty directory.
                block(&d.join("s.json"));
            }
        })
        .unwrap_err();
        assert!(err.contains("s.json was replaced and could not be put back"), "{err}");
        assert!(err.contains("its old content is in") && err.contains(TEMP_MARKER), "{err}");
        let kept = temporaries(dir.path());
        assert_eq!(kept.len(), 1, "{kept:?}");
        assert_eq!(std::fs::read(dir.path().join(&kept[0])).unwrap(), b"old stats");
    }

    /// Runs in a child process of its own (it closes this process's registry for good).
    #[test]
    fn remove_temporaries_removes_them_and_refuses_more() {
        const CHILD: &str = "BEAM_IO_REMOVE_TEMPORARIES_CHILD";
        if std::env::var_os(CHILD).is_none() {
            let child = std::process::Command::new(std::env::current_exe().unwrap())
                .args(["--exact", "io::tests::remove_temporaries_removes_them_and_refuses_more", "--test-threads=1"])
                .env(CHILD, "1")
                .output()
                .unwrap();
            let said = String::from_utf8_lossy(&child.stdout);
            assert!(child.status.success() && said.contains("1 passed"), "{said}");
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("o.png");
        std::fs::write(&out, b"old").unwrap();
        let (a, _file) = Temp::create(dir.path(), std::ffi::OsStr::new("o.png")).unwrap();
        let (b, _) = Temp::create(dir.path(), std::ffi::OsStr::new("s.json")).unwrap();
        assert_eq!(temporaries(dir.path()).len(), 2);
        assert_eq!(remove_temporaries(), 2);
        assert_eq!(temporaries(dir.path()).len(), 0);
        drop((a, b));
        let err = write_atomic(&out, b"new").unwrap_err().to_string();
        assert!(err.contains("interrupted"), "{err}");
        assert!(check_output(&out).is_err());
        assert_eq!(std::fs::read(&out).unwrap(), b"old");
        assert_eq!(entries(dir.path()), 1);
    }

    #[test]
    fn writes_and_replaces() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(entries(dir.path()), 1, "no temporary file left behind");
        let err = write_atomic(&dir.path().join("missing/b.txt"), b"x").unwrap_err().to_string();
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
        let err = write_atomic(&p, b"x").unwrap_err().to_string();
        assert!(err.contains("read-only") && std::fs::read(&p).unwrap() == b"new", "{err}");
        // A symbolic link is refused, and neither it nor its target changes.
        let target = dir.path().join("target");
        std::fs::write(&target, b"keep").unwrap();
        let link = dir.path().join("link.png");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let err = write_atomic(&link, b"x").unwrap_err().to_string();
        assert!(err.contains("symbolic link"), "{err}");
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"keep");
        assert!(write_atomic(Path::new("/dev/null"), b"x").unwrap_err().to_string().contains("device node"));
        assert!(write_atomic(dir.path(), b"x").unwrap_err().to_string().contains("directory"));
        // Two outputs: a failure on the second replaces neither.
        let q = dir.path().join("b.json");
        std::fs::write(&q, b"old").unwrap();
        let err = write_atomic_all(&[(&q, b"new"), (&dir.path().join("no/such"), b"x")]).unwrap_err().to_string();
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
