//! Output paths of `beam render`, `beam merge` and `beam compare`, checked before any work and
//! written together (the policy itself is [`beam_scene::io`]'s: regular files only, atomic, modes
//! kept), and the signal handling that removes the temporaries of an interrupted write.

use beam_render::image::Image;
use beam_scene::io::{check_output, encode_exr, encode_png_placed, same_file, write_atomic_all};
use beam_scene::region::Placement;
use std::path::Path;

/// The image formats written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Format {
    /// 8-bit sRGB.
    Png,
    /// OpenEXR, linear 32-bit float.
    Exr,
}

impl Format {
    /// The format `path` names by its extension (any case); an error naming `option` otherwise.
    pub(crate) fn of(option: &str, path: &Path) -> Result<Self, String> {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("png") => Ok(Self::Png),
            Some(e) if e.eq_ignore_ascii_case("exr") => Ok(Self::Exr),
            other => Err(format!(
                "{option} {}: {}; name the file *.png (8-bit sRGB) or *.exr (OpenEXR, linear float)",
                path.display(),
                other.map_or_else(|| "no extension".to_string(), |e| format!("unknown image format `.{e}`")),
            )),
        }
    }

    /// `PNG` or `OpenEXR`.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Png => "PNG",
            Self::Exr => "OpenEXR",
        }
    }
}

/// Refuse an image path whose extension is not `.png` (any case): for outputs written as PNG only.
pub(crate) fn check_png_name(option: &str, path: &Path) -> Result<(), String> {
    match Format::of(option, path) {
        Ok(Format::Png) => Ok(()),
        _ => Err(format!("{option} {}: only PNG is written; name the file *.png", path.display())),
    }
}

/// `--out` and `--stats` of `beam render`: a `.png` or `.exr` and a JSON file, different files,
/// each in a writable folder and absent or a writable regular file.
pub(crate) fn check_render_outputs(out: &Path, stats: Option<&Path>) -> Result<(), String> {
    Format::of("--out", out)?;
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

/// The bytes of `image` (the pixels of `placement`) in the format `out` names, scaled by
/// 2^`exposure` first: PNG as 8-bit sRGB, EXR as linear `f32`; each records the placement when it
/// is not the whole frame.
pub(crate) fn encode_render(out: &Path, image: &Image, placement: Placement, exposure: f32) -> Result<Vec<u8>, String> {
    let scale = exposure.exp2();
    let scaled;
    let image = if scale == 1.0 {
        image
    } else {
        scaled = Image { pixels: image.pixels.iter().map(|&c| c * scale).collect(), ..*image };
        &scaled
    };
    let bytes = match Format::of("--out", out)? {
        Format::Png => encode_png_placed(&image.to_srgb8(), placement),
        Format::Exr => encode_exr(&image.pixels, placement),
    };
    bytes.map_err(|e| format!("{}: {e}", out.display()))
}

/// Write `image` (the pixels of `placement`, scaled by 2^`exposure`) to `out` and the statistics to
/// `stats` (when given), both or neither: both are written and synced under temporary names before
/// either is renamed.
pub(crate) fn write_render(
    out: &Path,
    image: &Image,
    (placement, exposure): (Placement, f32),
    stats: Option<(&Path, &dyn erased::Json)>,
) -> Result<(), String> {
    let bytes = encode_render(out, image, placement, exposure)?;
    if let Some(warning) = exposure_warning(image, exposure) {
        // Said even when `quiet`: the picture shows nothing.
        eprintln!("warning: {}: {warning}", out.display());
    }
    match stats {
        None => write_atomic_all(&[(out, &bytes)]).map_err(|e| e.to_string()),
        Some((path, s)) => {
            let json = s.to_json().map_err(|e| format!("{}: {e}", path.display()))?;
            write_atomic_all(&[(path, json.as_bytes()), (out, &bytes)]).map_err(|e| e.to_string())
        }
    }
}

/// Why `image` scaled by 2^`exposure` shows nothing, if it does not: every pixel black in 8-bit
/// sRGB (below half a step) or every pixel white (each channel at 1 or above), with the exposure
/// that would bring its brightest (or darkest) pixel to 0.8.
fn exposure_warning(image: &Image, exposure: f32) -> Option<String> {
    let scale = exposure.exp2();
    let brightest = image.pixels.iter().map(|c| c.max_element()).fold(0.0f32, f32::max) * scale;
    let darkest = image.pixels.iter().map(|c| c.min_element()).fold(f32::INFINITY, f32::min) * scale;
    let to = |level: f32| exposure + (0.8 / level).log2();
    // Linear radiance below which sRGB 8-bit rounds to 0: half a step, 0.5/255 / 12.92.
    if brightest < 0.5 / 255.0 / 12.92 {
        Some(if brightest > 0.0 {
            format!("the image is all black (brightest pixel {brightest:.1e}); try --exposure {:.1}", to(brightest))
        } else {
            "the image is all black: no light reaches the camera (check the lights and the camera)".into()
        })
    } else if darkest >= 1.0 && darkest.is_finite() {
        Some(format!("the image is all white (darkest pixel {darkest:.2}); try --exposure {:.1}", to(darkest)))
    } else {
        None
    }
}

/// Statistics of any type, as JSON.
pub(crate) mod erased {
    /// A value written as pretty JSON.
    pub(crate) trait Json {
        /// The JSON text.
        fn to_json(&self) -> Result<String, String>;
    }

    impl<T: serde::Serialize> Json for T {
        fn to_json(&self) -> Result<String, String> {
            serde_json::to_string_pretty(self).map_err(|e| e.to_string())
        }
    }
}

/// Set, in the signal handler itself, to the number of the `SIGINT`, `SIGTERM` or `SIGHUP` that
/// arrived (0 while none has).
#[cfg(unix)]
static STOPPED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// Stop cleanly on `SIGINT`, `SIGTERM` and `SIGHUP`: a thread waits for one and [`stop`]s, and so
/// does [`wait_if_stopped`] when the work ended meanwhile. The waiting thread's self-pipe is
/// registered before the flag, so no signal can set the flag unseen by that thread. A second
/// signal changes nothing: the handlers stay installed until the exit. `SIGKILL` cannot be caught.
#[cfg(unix)]
pub(crate) fn stop_cleanly_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let warn = |e: &dyn std::fmt::Display| {
        eprintln!("warning: no signal handler ({e}): an interrupted write may leave a temporary");
    };
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        Ok(s) => s,
        Err(e) => return warn(&e),
    };
    let waiter = std::thread::Builder::new().name("signals".into()).spawn(move || {
        if let Some(signal) = signals.forever().next() {
            stop(signal);
        }
    });
    if let Err(e) = waiter {
        warn(&e);
    }
    for signal in [SIGINT, SIGTERM, SIGHUP] {
        if let Err(e) = signal_hook::flag::register_usize(signal, &STOPPED, signal as usize) {
            return warn(&e);
        }
    }
}

/// Remove the temporaries of outputs being written ([`beam_scene::io::remove_temporaries`], which
/// waits for a group of renames in progress to finish or be undone), say so, and exit with status
/// 128 + `signal` (130 for Ctrl-C).
#[cfg(unix)]
fn stop(signal: i32) -> ! {
    static STOPPING: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
    if STOPPING.swap(true, std::sync::atomic::Ordering::SeqCst) {
        // The other caller exits.
        loop {
            std::thread::park();
        }
    }
    let removed = beam_scene::io::remove_temporaries();
    let name = signal_hook::low_level::signal_name(signal).unwrap_or("a signal");
    let what = if removed > 0 { "; the unfinished outputs were removed" } else { "" };
    eprintln!("\nbeam: stopped by {name}{what}");
    // `_exit`: no at-exit handlers run while other threads (rayon, a GPU driver) still do.
    signal_hook::low_level::exit(128 + signal)
}

/// When a signal has arrived, [`stop`] instead of returning: a signal that came before the end,
/// however late, gives its status, not the work's.
#[cfg(unix)]
pub(crate) fn wait_if_stopped() {
    let signal = STOPPED.load(std::sync::atomic::Ordering::SeqCst);
    if signal != 0 {
        stop(signal as i32);
    }
}

/// Signals are not handled on this platform.
#[cfg(not(unix))]
pub fn stop_cleanly_on_signals() {}

/// Signals are not handled on this platform.
#[cfg(not(unix))]
pub fn wait_if_stopped() {}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_math::glam::Vec3;

    fn image(pixels: Vec<Vec3>) -> Image {
        Image { width: pixels.len() as u32, height: 1, pixels }
    }

    #[test]
    fn black_and_white_images_are_named() {
        let dim = image(vec![Vec3::ZERO, Vec3::splat(1e-5)]);
        let w = exposure_warning(&dim, 0.0).expect("all black");
        assert!(w.contains("all black") && w.contains("--exposure 16."), "{w}");
        assert!(exposure_warning(&dim, 16.0).is_none(), "brought up by the exposure");
        assert!(exposure_warning(&image(vec![Vec3::ZERO; 4]), 0.0).unwrap().contains("no light"));
        let w = exposure_warning(&image(vec![Vec3::splat(4.0), Vec3::splat(8.0)]), 0.0).expect("all white");
        assert!(w.contains("all white") && w.contains("--exposure -2.3"), "{w}");
        assert!(exposure_warning(&image(vec![Vec3::ZERO, Vec3::ONE]), 0.0).is_none());
    }
}
