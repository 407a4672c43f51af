//! The `--scenes` of `beam bench primary`, `gpu` and `glossy` ([`SceneList`], one argument group
//! flattened into each): scenes by name, comma-separated, each bench's own list when none is given.

/// Scenes to run a bench on.
#[derive(clap::Args)]
pub(crate) struct SceneList {
    /// Scenes, comma-separated: built-ins, and for `primary` also .toml scenes, .obj meshes and the
    /// shared `sponza` and `conference` (default: the bench's own list, in its help).
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
}

impl SceneList {
    /// The scenes given, or `defaults` where none were.
    pub(super) fn or(self, defaults: &[&str]) -> Vec<String> {
        match self.scenes.is_empty() {
            true => defaults.iter().map(|&s| s.to_owned()).collect(),
            false => self.scenes,
        }
    }
}
