//! A progress bar on a terminal, nothing otherwise (indicatif hides itself when stderr is not a tty).

use indicatif::{ProgressBar, ProgressStyle};

/// A bar of `len` steps with a message.
pub(crate) fn bar(len: u64, message: &'static str) -> ProgressBar {
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} {elapsed}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(message);
    bar
}
