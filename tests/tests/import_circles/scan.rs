//! Scanner: module declarations, `use` trees and qualified paths, each with the inline-module
//! scope it appears in.

use super::lex::{Tok, Token, ident, opening, path_sep, punct, skip_group};

/// A `mod name;` or `mod name { .. }` declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ModDecl {
    /// Inline modules around the declaration, outermost first.
    pub(crate) scope: Vec<String>,
    pub(crate) name: String,
    pub(crate) inline: bool,
}

/// One path named by the file: a leaf of a `use` tree or a qualified path in code.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct PathRef {
    pub(crate) scope: Vec<String>,
    pub(crate) segments: Vec<String>,
    pub(crate) line: usize,
    /// The name a `use` binds (`as` alias or last segment); `None` for globs and code paths.
    pub(crate) binds: Option<String>,
}

#[derive(Debug, Default)]
pub(crate) struct Scan {
    pub(crate) mods: Vec<ModDecl>,
    pub(crate) uses: Vec<PathRef>,
    pub(crate) code: Vec<PathRef>,
}

/// Whether the attributes and visibility just before the `mod` at `i` include `#[cfg(test)]` (or a
/// `cfg` that requires `test`).
pub(crate) fn cfg_test_before(tokens: &[Token], i: usize) -> bool {
    let mut j = i;
    while j > 0 {
        let k = j - 1;
        if ident(tokens, k) == Some("pub") {
            j = k;
        } else if punct(tokens, k, ')') {
            // `pub(crate)`, `pub(in a::b)`: back to the `(`.
            let Some(m) = opening(tokens, k, '(', ')') else { return false };
            j = m;
        } else if punct(tokens, k, ']') {
            let Some(m) = opening(tokens, k, '[', ']') else { return false };
            let body = &tokens[m + 1..k];
            let is_cfg = matches!(body.first().map(|t| &t.tok), Some(Tok::Ident(s)) if s == "cfg");
            let names = |word: &str| body.iter().any(|t| t.tok == Tok::Ident(word.into()));
            if is_cfg && names("test") && !names("not") {
                return true;
            }
            // Back over `#` (and `!` of an inner attribute).
            j = m;
            if j > 0 && punct(tokens, j - 1, '!') {
                j -= 1;
            }
            if j > 0 && punct(tokens, j - 1, '#') {
                j -= 1;
            } else {
                return false;
            }
        } else {
            return false;
        }
    }
    false
}

/// Parses one `use` tree at `*i`, appending its leaves to `out` as (segments, bound name).
pub(crate) fn parse_use_tree(
    tokens: &[Token],
    i: &mut usize,
    prefix: Vec<String>,
    out: &mut Vec<(Vec<String>, Option<String>)>,
) {
    let mut segs = prefix;
    if path_sep(tokens, *i) {
        // `use ::std::..`: an extern crate.
        segs.push("::".into());
        *i += 1;
    }
    loop {
        if punct(tokens, *i, '{') {
            *i += 1;
            while *i < tokens.len() && !punct(tokens, *i, '}') {
                let before = *i;
                parse_use_tree(tokens, i, segs.clone(), out);
                if punct(tokens, *i, ',') {
                    *i += 1;
                }
                if *i == before {
                    *i += 1;
                }
            }
            *i += 1;
            return;
        }
        if punct(tokens, *i, '*') {
            *i += 1;
            out.push((segs, None));
            return;
        }
        let name = if punct(tokens, *i, '$') && ident(tokens, *i + 1) == Some("crate") {
            *i += 1;
            "crate".to_string()
        } else if let Some(name) = ident(tokens, *i) {
            name.to_string()
        } else {
            return;
        };
        *i += 1;
        if name == "self" && !segs.is_empty() {
            // `a::{self}`: the prefix itself.
        } else {
            segs.push(name);
        }
        if path_sep(tokens, *i) {
            *i += 1;
            continue;
        }
        let mut binds = segs.last().cloned();
        if ident(tokens, *i) == Some("as") {
            binds = ident(tokens, *i + 1).map(str::to_string);
            *i += 2;
        }
        if binds.as_deref() == Some("_") {
            binds = None;
        }
        out.push((segs, binds));
        return;
    }
}

pub(crate) fn scan(tokens: &[Token]) -> Scan {
    let mut result = Scan::default();
    // One entry per open `{`: the inline module it opens, if any.
    let mut braces: Vec<Option<String>> = Vec::new();
    let scope_of = |braces: &[Option<String>]| braces.iter().flatten().cloned().collect::<Vec<_>>();
    let mut i = 0;
    while i < tokens.len() {
        let line = tokens[i].line;
        match &tokens[i].tok {
            Tok::Punct('{') => {
                braces.push(None);
                i += 1;
            }
            Tok::Punct('}') => {
                braces.pop();
                i += 1;
            }
            Tok::Punct('#')
                if punct(tokens, i + 1, '[') || (punct(tokens, i + 1, '!') && punct(tokens, i + 2, '[')) =>
            {
                // Attributes hold no imports (`cfg` values, lint names, doc strings).
                let open = if punct(tokens, i + 1, '[') { i + 1 } else { i + 2 };
                i = skip_group(tokens, open, '[', ']');
            }
            Tok::Ident(word) if word == "pub" && punct(tokens, i + 1, '(') && ident(tokens, i + 2) == Some("in") => {
                // `pub(in crate::a)` restricts visibility; it imports nothing.
                i = skip_group(tokens, i + 1, '(', ')');
            }
            Tok::Ident(word)
                if word == "mod"
                    && ident(tokens, i + 1).is_some()
                    && (punct(tokens, i + 2, ';') || punct(tokens, i + 2, '{')) =>
            {
                let name = ident(tokens, i + 1).unwrap_or_default().to_string();
                let inline = punct(tokens, i + 2, '{');
                if inline && cfg_test_before(tokens, i) {
                    // Inline unit tests: not part of the crate's structure.
                    i = skip_group(tokens, i + 2, '{', '}');
                    continue;
                }
                result.mods.push(ModDecl { scope: scope_of(&braces), name: name.clone(), inline });
                if inline {
                    braces.push(Some(name));
                }
                i += 3;
            }
            Tok::Ident(word) if word == "use" && !punct(tokens, i + 1, '<') => {
                i += 1;
                let mut leaves = Vec::new();
                parse_use_tree(tokens, &mut i, Vec::new(), &mut leaves);
                let scope = scope_of(&braces);
                for (segments, binds) in leaves {
                    result.uses.push(PathRef { scope: scope.clone(), segments, line, binds });
                }
                while i < tokens.len() && !punct(tokens, i, ';') {
                    i += 1;
                }
            }
            _ => {
                // A qualified path in code: `a::b::c` not preceded by `::` (`$crate::` counts as `crate::`).
                let dollar_crate = punct(tokens, i, '$') && ident(tokens, i + 1) == Some("crate");
                let start = if dollar_crate { i + 1 } else { i };
                let first = ident(tokens, start);
                let after_sep = i > 0 && path_sep(tokens, i - 1);
                if let (Some(first), false, true) = (first, after_sep, path_sep(tokens, start + 1)) {
                    let mut segments = vec![first.to_string()];
                    let mut j = start + 1;
                    while path_sep(tokens, j) {
                        match ident(tokens, j + 1) {
                            Some(s) => segments.push(s.to_string()),
                            None => break,
                        }
                        j += 2;
                    }
                    result.code.push(PathRef { scope: scope_of(&braces), segments, line, binds: None });
                    i = j;
                } else {
                    i += 1;
                }
            }
        }
    }
    result
}
