//! Output paths of `beam render` and `beam compare`, checked before any work and written together
//! (the policy itself is [`beam_cpu::io`]'s: regular files only, atomic, modes kept).

use beam_cpu::io::{check_output, encode_png, same_file, write_atomic_all};
use beam_cpu::render::Image;
use std::path::Path;

/// Refuse an image path whose extension is not `.png` (any case): only PNG is written.
pub fn check_png_name(option: &str, path: &Path) -> Result<(), String> {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("png") => Ok(()),
        _ => Err(format!("{option} {}: only PNG is written; name the file *.png", path.display())),
    }
}

/// `--out` and `--stats` of `beam render`: a `.png` and a JSON file, different files, each in a
/// writable folder and absent or a writable regular file.
pub fn check_render_outputs(out: &Path, stats: Option<&Path>) -> Result<(), String> {
    check_png_name("--out", out)?;
    if let Some(s) = stats {
        if same_file(out, s) {
            return Err(format!(
                "--out {} and --stats {} name the same file; give them different names",
                out.display(),
                s.display()
            ));
        }
    }
    check_output(out).map_err(|e| format!("--out {e}"))?;
    if let Some(s) = stats {
        check_output(s).map_err(|e| format!("--stats {e}"))?;
    }
    Ok(())
}

/// Write the image to `out` and the statistics to `stats` (when given), both or neither: both are
/// written and synced under temporary names before either is renamed.
pub fn write_render(out: &Path, image: &Image, stats: Option<(&Path, &dyn erased::Json)>) -> Result<(), String> {
    let png =
        encode_png(image.width, image.height, &image.to_srgb8()).map_err(|e| format!("{}: {e}", out.display()))?;
    match stats {
        None => write_atomic_all(&[(out, &png)]),
        Some((path, s)) => {
            let json = s.to_json().map_err(|e| format!("{}: {e}", path.display()))?;
            write_atomic_all(&[(path, json.as_bytes()), (out, &png)])
        }
    }
}

/// Statistics of any type, as JSON.
pub mod erased {
    /// A value written as pretty JSON.
    pub trait Json {
        /// The JSON text.
        fn to_json(&self) -> Result<String, String>;
    }

    impl<T: serde::Serialize> Json for T {
        fn to_json(&self) -> Result<String, String> {
            serde_json::to_string_pretty(self).map_err(|e| e.to_string())
        }
    }
}
