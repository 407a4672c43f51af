//! Lexer: identifiers, `::` and single punctuation; comments, strings, chars and lifetimes
//! dropped; and the token tests the scanner reads with.

#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Tok {
    Ident(String),
    PathSep,
    Punct(char),
}

#[derive(Debug, Clone)]
pub(crate) struct Token {
    pub(crate) tok: Tok,
    pub(crate) line: usize,
}

pub(crate) fn is_ident_start(c: char) -> bool {
    c == '_' || c.is_alphabetic()
}

pub(crate) fn is_ident_continue(c: char) -> bool {
    c == '_' || c.is_alphanumeric()
}

pub(crate) fn lex(src: &str) -> Vec<Token> {
    let chars: Vec<char> = src.chars().collect();
    let n = chars.len();
    let at = |i: usize| if i < n { chars[i] } else { '\0' };
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    // Advances over `chars[from..to]`, counting newlines.
    let count_lines = |from: usize, to: usize| chars[from..to.min(n)].iter().filter(|&&c| c == '\n').count();
    while i < n {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c == '/' && at(i + 1) == '/' {
            while i < n && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && at(i + 1) == '*' {
            let start = i;
            let mut depth = 0;
            while i < n {
                if chars[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            line += count_lines(start, i);
        } else if c == '"' {
            let start = i;
            i += 1;
            while i < n && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            line += count_lines(start, i);
        } else if c == '\'' {
            if at(i + 1) == '\\' {
                // Escaped char literal: '\n', '\'', '\u{..}'.
                i += 3;
                while i < n && chars[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(i + 2) == '\'' {
                i += 3;
            } else {
                // Lifetime or label.
                i += 1;
                while i < n && is_ident_continue(chars[i]) {
                    i += 1;
                }
            }
        } else if is_ident_start(c) {
            let start = i;
            while i < n && is_ident_continue(chars[i]) {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let raw_prefix = matches!(word.as_str(), "r" | "br" | "cr");
            if raw_prefix && (at(i) == '"' || (at(i) == '#' && (at(i + 1) == '#' || at(i + 1) == '"'))) {
                // Raw string: r"..", r#".."#, br##".."##.
                let start = i;
                let mut hashes = 0;
                while at(i) == '#' {
                    hashes += 1;
                    i += 1;
                }
                i += 1;
                loop {
                    if i >= n {
                        break;
                    }
                    if chars[i] == '"' && (1..=hashes).all(|k| at(i + k) == '#') {
                        i += 1 + hashes;
                        break;
                    }
                    i += 1;
                }
                line += count_lines(start, i);
            } else if word == "r" && at(i) == '#' && is_ident_start(at(i + 1)) {
                // Raw identifier: r#type.
                i += 1;
                let start = i;
                while i < n && is_ident_continue(chars[i]) {
                    i += 1;
                }
                out.push(Token { tok: Tok::Ident(chars[start..i].iter().collect()), line });
            } else if (word == "b" || word == "c") && at(i) == '"' {
                // Byte or C string: the `"` branch skips the body.
            } else if word == "b" && at(i) == '\'' {
                // Byte char: b'x', b'\n'.
                i += if at(i + 1) == '\\' { 3 } else { 2 };
                while i < n && chars[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else {
                out.push(Token { tok: Tok::Ident(word), line });
            }
        } else if c.is_ascii_digit() {
            while i < n && (is_ident_continue(chars[i]) || (chars[i] == '.' && at(i + 1).is_ascii_digit())) {
                i += 1;
            }
        } else if c == ':' && at(i + 1) == ':' {
            out.push(Token { tok: Tok::PathSep, line });
            i += 2;
        } else {
            out.push(Token { tok: Tok::Punct(c), line });
            i += 1;
        }
    }
    out
}

pub(crate) fn ident(tokens: &[Token], i: usize) -> Option<&str> {
    match tokens.get(i).map(|t| &t.tok) {
        Some(Tok::Ident(s)) => Some(s),
        _ => None,
    }
}

pub(crate) fn punct(tokens: &[Token], i: usize, c: char) -> bool {
    matches!(tokens.get(i).map(|t| &t.tok), Some(Tok::Punct(p)) if *p == c)
}

pub(crate) fn path_sep(tokens: &[Token], i: usize) -> bool {
    matches!(tokens.get(i).map(|t| &t.tok), Some(Tok::PathSep))
}

/// The index just past the group that opens at `i` (`open` .. matching `close`).
pub(crate) fn skip_group(tokens: &[Token], i: usize, open: char, close: char) -> usize {
    let mut depth = 0;
    let mut j = i;
    while j < tokens.len() {
        if punct(tokens, j, open) {
            depth += 1;
        } else if punct(tokens, j, close) {
            depth -= 1;
            if depth == 0 {
                return j + 1;
            }
        }
        j += 1;
    }
    tokens.len()
}

/// The index of the `open` that matches the `close` at `k`, searching backwards; `None` where
/// there is none.
pub(crate) fn opening(tokens: &[Token], k: usize, open: char, close: char) -> Option<usize> {
    let mut depth = 0;
    for m in (0..=k).rev() {
        if punct(tokens, m, close) {
            depth += 1;
        } else if punct(tokens, m, open) {
            depth -= 1;
            if depth == 0 {
                return Some(m);
            }
        }
    }
    None
}
