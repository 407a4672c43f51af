//! The temporary files (and backups) of [`super`]'s writes: made under fresh
//! `.NAME.beam-tmp-XXXX` names, registered while they exist, so that [`remove_temporaries`] can
//! delete them when the program is stopped.

use std::fs::{File, OpenOptions};
use std::hash::{BuildHasher, Hasher};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The marker of temporary names: `.NAME.beam-tmp-XXXXXXXXXXXXXXXX`.
pub const TEMP_MARKER: &str = ".beam-tmp-";

/// The temporaries of this process that exist now, and whether [`remove_temporaries`] has run.
pub(super) struct Registry {
    live: Vec<PathBuf>,
    pub(super) closed: bool,
}

impl Registry {
    /// Forget `path`; false when it was not registered (already removed by [`remove_temporaries`]).
    fn forget(&mut self, path: &Path) -> bool {
        let before = self.live.len();
        self.live.retain(|p| p != path);
        self.live.len() != before
    }
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry { live: Vec::new(), closed: false });

/// The registry, locked (a panic elsewhere while it was held does not make it unusable).
pub(super) fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The error of a write asked for after [`remove_temporaries`].
pub(super) fn interrupted() -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::Interrupted, "interrupted: the program is stopping")
}

/// Remove every temporary file (and backup) this process has created and not yet renamed or
/// removed, and make every later write of this module fail; returns how many were removed.
///
/// For a program's signal handling: call it, then exit. It waits until a group of renames in
/// progress ([`super::write_atomic_all`]) has finished or been rolled back. It takes a lock and
/// allocates, so call it from an ordinary thread (such as one waiting on signals through a
/// self-pipe), never from inside an asynchronous signal handler.
pub fn remove_temporaries() -> usize {
    let mut reg = registry();
    reg.closed = true;
    let live = std::mem::take(&mut reg.live);
    live.iter().filter(|p| std::fs::remove_file(p).is_ok()).count()
}

/// Make a new file at a fresh `.NAME.beam-tmp-XXXX` in `dir` with `make` (which fails with
/// `AlreadyExists` when the name is taken), and register it. Its path, and what `make` returned.
fn make_registered<T>(
    reg: &mut Registry,
    dir: &Path,
    name: &std::ffi::OsStr,
    mut make: impl FnMut(&Path) -> std::io::Result<T>,
) -> std::io::Result<(PathBuf, T)> {
    if reg.closed {
        return Err(interrupted());
    }
    let mut last = None;
    for _ in 0..16 {
        let mut h = std::collections::hash_map::RandomState::new().build_hasher();
        h.write_u32(std::process::id());
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!("{TEMP_MARKER}{:016x}", h.finish()));
        let path = dir.join(tmp_name);
        match make(&path) {
            Ok(made) => {
                reg.live.push(path.clone());
                return Ok((path, made));
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| std::io::Error::other("no free temporary name")))
}

/// A registered temporary file beside its target (or a backup of the target), removed on drop
/// unless renamed or kept.
pub(super) struct Temp {
    pub(super) path: PathBuf,
    done: bool,
}

impl Temp {
    /// Create `.NAME.beam-tmp-XXXX` in `dir`, with the default mode (`0o666` less the umask).
    pub(super) fn create(dir: &Path, name: &std::ffi::OsStr) -> std::io::Result<(Self, File)> {
        let open = |p: &Path| OpenOptions::new().write(true).create_new(true).open(p);
        let (path, file) = make_registered(&mut registry(), dir, name, open)?;
        Ok((Self { path, done: false }, file))
    }

    /// Keep `target`'s current content under a new `.NAME.beam-tmp-XXXX` name in `dir`: a hard
    /// link, or a synced copy where the file system has none.
    pub(super) fn backup(
        reg: &mut Registry,
        dir: &Path,
        name: &std::ffi::OsStr,
        target: &Path,
    ) -> std::io::Result<Self> {
        let link = |p: &Path| std::fs::hard_link(target, p);
        let (path, ()) = match make_registered(reg, dir, name, link) {
            Ok(made) => made,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => return Err(e),
            Err(_) => make_registered(reg, dir, name, |p| {
                let mut from = File::open(target)?;
                let mut to = OpenOptions::new().write(true).create_new(true).open(p)?;
                let done = std::io::copy(&mut from, &mut to)
                    .and_then(|_| to.set_permissions(from.metadata()?.permissions()))
                    .and_then(|()| to.sync_all());
                if let Err(e) = done {
                    let _ = std::fs::remove_file(p);
                    // Not `AlreadyExists`, which would try another name.
                    return Err(std::io::Error::other(e));
                }
                Ok(())
            })?,
        };
        Ok(Self { path, done: false })
    }

    /// Rename the temporary to `to`; the caller holds the registry.
    pub(super) fn rename(&mut self, reg: &mut Registry, to: &Path) -> std::io::Result<()> {
        std::fs::rename(&self.path, to)?;
        reg.forget(&self.path);
        self.done = true;
        Ok(())
    }

    /// Leave the file where it is, unregistered.
    pub(super) fn keep(&mut self, reg: &mut Registry) {
        reg.forget(&self.path);
        self.done = true;
    }

    /// Remove the file, unless [`remove_temporaries`] already has; the caller holds the registry.
    pub(super) fn remove(&mut self, reg: &mut Registry) {
        if !self.done && reg.forget(&self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
        self.done = true;
    }
}

impl Drop for Temp {
    fn drop(&mut self) {
        if !self.done {
            self.remove(&mut registry());
        }
    }
}
