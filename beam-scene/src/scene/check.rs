//! Checks of scene-file text and values: nesting depth before parsing, TOML errors as
//! `file:line:column`, and values (colours, positions) that must be finite or non-negative.

use crate::error::SceneError;
use crate::read::{QUOTE_CHARS, clip, visible};
use std::path::Path;

/// Deepest nesting of arrays and inline tables in a scene file (a scene needs 3).
pub(super) const MAX_DEPTH: usize = 64;

/// Refuse text whose arrays and inline tables nest deeper than [`MAX_DEPTH`] before the TOML
/// parser (which recurses) sees it. A cheap scan that skips strings and comments; the error names
/// the file and line. (Deep dotted keys the parser refuses itself, without recursing.)
pub(super) fn nesting(path: &Path, text: &str) -> Result<(), SceneError> {
    let b = text.as_bytes();
    let (mut i, mut line, mut depth) = (0, 1, 0usize);
    let fail = |line: usize, what: &str| {
        Err(SceneError::Toml {
            path: path.to_path_buf(),
            line: Some(line),
            column: None,
            message: format!("{what} nest deeper than {MAX_DEPTH} levels"),
        })
    };
    while i < b.len() {
        match b[i] {
            b'\n' => line += 1,
            b'#' => {
                while i + 1 < b.len() && b[i + 1] != b'\n' {
                    i += 1;
                }
            }
            q @ (b'"' | b'\'') => {
                let long = b[i..].starts_with(if q == b'"' { b"\"\"\"" } else { b"'''" });
                i += if long { 3 } else { 1 };
                // Skip to the closing quote(s); basic strings have backslash escapes.
                while i < b.len() {
                    if q == b'"' && b[i] == b'\\' {
                        i += 2;
                        continue;
                    }
                    if b[i] == b'\n' {
                        line += 1;
                        if !long {
                            break;
                        }
                    }
                    if b[i] == q && (!long || b[i..].starts_with(&[q, q, q])) {
                        i += if long { 2 } else { 0 };
                        break;
                    }
                    i += 1;
                }
            }
            b'[' | b'{' => {
                depth += 1;
                if depth > MAX_DEPTH {
                    return fail(line, "arrays or tables");
                }
            }
            b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        i += 1;
    }
    Ok(())
}

/// A TOML error as `file:line:column: message`, quoting at most [`QUOTE_CHARS`] characters of the
/// line around the column (the parser's own message quotes the whole line, however long).
pub(super) fn toml_error(path: &Path, text: &str, e: &toml::de::Error) -> SceneError {
    let message = match e.message().trim() {
        "" => "not valid TOML".to_string(),
        m => visible(&clip(&m.replace('\n', "; "), 200)),
    };
    let toml = |line, column, message| SceneError::Toml { path: path.to_path_buf(), line, column, message };
    let Some(span) = e.span() else {
        return toml(None, None, message);
    };
    // An error at the very end points at the last line, not the empty one after it.
    let end = if text.ends_with('\n') { text.len() - 1 } else { text.len() };
    let at = (0..=span.start.min(end)).rev().find(|&k| text.is_char_boundary(k)).unwrap_or(0);
    let line_start = text[..at].rfind('\n').map_or(0, |k| k + 1);
    let line_end = text[at..].find('\n').map_or(text.len(), |k| at + k);
    let line = text[..at].matches('\n').count() + 1;
    let column = text[line_start..at].chars().count();
    let chars: Vec<char> = text[line_start..line_end].trim_end().chars().collect();
    let from = column.saturating_sub(QUOTE_CHARS / 2).min(chars.len().saturating_sub(QUOTE_CHARS));
    let to = (from + QUOTE_CHARS).min(chars.len());
    let mut quoted: String = chars[from..to].iter().collect();
    if from > 0 {
        quoted.insert(0, '…');
    }
    if to < chars.len() {
        quoted.push('…');
    }
    let quoted = visible(quoted.trim());
    let message = if quoted.is_empty() { message } else { format!("{message}: `{quoted}`") };
    toml(Some(line), Some(column + 1), message)
}

/// Refuse non-finite values of `element` (a position, a transform).
pub(super) fn finite(path: &Path, element: &str, values: &[f32]) -> Result<(), SceneError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            path: path.to_path_buf(),
            element: element.to_string(),
            message: format!("values must be finite, not {values:?}"),
        })
    }
}

/// Refuse a colour (albedo, tint, radiance, intensity) of `element` that is not finite and ≥ 0.
pub(super) fn colour(path: &Path, element: &str, rgb: [f32; 3]) -> Result<(), SceneError> {
    if rgb.iter().all(|v| v.is_finite() && *v >= 0.0) {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            path: path.to_path_buf(),
            element: element.to_string(),
            message: format!("each channel must be finite and ≥ 0, not {rgb:?}"),
        })
    }
}

/// A name from a scene file made safe to print: control characters escaped, clipped.
pub(super) fn name(s: &str) -> String {
    clip(&s.escape_debug().to_string(), QUOTE_CHARS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_nesting_is_refused_outside_strings_and_comments() {
        let p = Path::new("s.toml");
        assert!(nesting(p, "a = [[1], [2]]\n[[meshes]]\nb = { c = [1.5, 2.5] }\n").is_ok());
        let deep = format!("x = 1\na = {}1{}\n", "[".repeat(100), "]".repeat(100));
        let e = nesting(p, &deep).unwrap_err().to_string();
        assert_eq!(e, "s.toml:2: arrays or tables nest deeper than 64 levels");
        let quoted = format!(
            "a = \"{}\"\nb = '{}'\n# {}\nc = \"\"\"\n{}\"\"\"\n",
            "[".repeat(99),
            "{".repeat(99),
            "[".repeat(99),
            "[".repeat(99)
        );
        assert!(nesting(p, &quoted).is_ok());
        let dotted = format!("{} = 1\n", ["a"; 100_000].join("."));
        assert!(nesting(p, &dotted).is_ok());
        let e = toml::from_str::<toml::Value>(&dotted).unwrap_err();
        let m = toml_error(p, &dotted, &e).to_string();
        assert!(m.starts_with("s.toml:1:") && m.len() < 400, "{m}");
    }

    #[test]
    fn toml_errors_are_short_and_name_the_line() {
        let p = Path::new("s.toml");
        let text = format!("a = 1\nb = [{}\n", "1, ".repeat(10_000));
        let e = toml::from_str::<toml::Value>(&text).unwrap_err();
        let m = toml_error(p, &text, &e).to_string();
        assert!(m.starts_with("s.toml:2:") && m.len() < 400, "{m}");
    }
}
