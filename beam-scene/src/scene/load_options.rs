//! How a scene file may name other files: the options every loader (TOML, glTF, OBJ) takes.

/// How a scene file may name other files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Let mesh paths lead outside the scene file's folder (`beam render --allow-outside-paths`);
    /// lines of such files are still never quoted in errors.
    pub allow_outside_paths: bool,
}
