//! Text for messages: file contents and paths quoted in errors, clipped and with control
//! characters escaped, and sizes in words. The errors ([`crate::error`]) and the readers
//! ([`crate::read`] and the parsers behind it) both use it, so it depends on neither.

use std::path::Path;

/// Most characters of a file's line quoted in an error.
pub const QUOTE_CHARS: usize = 80;

/// `n` bytes in words (`4 MiB`).
pub(crate) fn bytes(n: u64) -> String {
    if n >= 1 << 30 && n % (1 << 30) == 0 {
        format!("{} GiB", n >> 30)
    } else if n >= 1 << 20 && n % (1 << 20) == 0 {
        format!("{} MiB", n >> 20)
    } else {
        format!("{n} bytes")
    }
}

/// `path` for an error message, clipped to 240 characters (a scene file may name a path of
/// thousands).
#[must_use]
pub fn shown(path: &Path) -> String {
    clip(&path.display().to_string(), 240)
}

/// `line` trimmed and clipped to [`QUOTE_CHARS`] characters (with `…` when clipped), control and
/// text-direction characters escaped, for quoting in an error.
#[must_use]
pub fn quote(line: &str) -> String {
    visible(&clip(line.trim(), QUOTE_CHARS))
}

/// `text` with control characters (but tab) and text-direction overrides escaped (`\u{202e}`), so
/// that a quoted line shows what the file holds and cannot rewrite the terminal.
#[must_use]
pub fn visible(text: &str) -> String {
    let hidden =
        |c: char| (c.is_control() && c != '\t') || matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}');
    text.chars().map(|c| if hidden(c) { c.escape_unicode().to_string() } else { c.to_string() }).collect()
}

/// `text` cut to at most `max` characters, ending in `…` when cut.
#[must_use]
pub fn clip(text: &str, max: usize) -> String {
    match text.char_indices().nth(max) {
        None => text.to_string(),
        Some((end, _)) => format!("{}…", &text[..end]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clips_quotes_on_character_boundaries() {
        assert_eq!(quote("  v 1 2  "), "v 1 2");
        let long = "é".repeat(200);
        let q = quote(&long);
        assert_eq!(q.chars().count(), QUOTE_CHARS + 1);
        assert!(q.ends_with('…'));
        assert_eq!(quote("v\u{1b}[2J 1\u{202e}\t2"), "v\\u{1b}[2J 1\\u{202e}\t2");
    }
}
