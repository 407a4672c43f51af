//! No import circles inside a crate.
//!
//! Take the `.rs` files of one crate as the nodes of a graph. File `a` has an edge to file `b` when `a`
//! names something in `b`'s module: a `use` (re-exports with `pub use` included) or a qualified path in
//! code (`super::x::Y`, `crate::a::b::c`, `self::...`, `child::Item`). An *import circle* is a cycle in
//! that graph: `a` reaches `b` and `b` reaches `a` again. Declaring a child with `mod x;` is structure,
//! not an edge; but a child that takes `super::Foo` from its parent's file while the parent takes items
//! from that child is a circle.
//!
//! We forbid circles so that every file has one job and the crate can be read bottom-up: each file
//! uses only files below it, and a reader (or a reviewer, or a refactor) can understand a file knowing
//! only what it imports. A circle means two files are one job split in two, or that a shared piece
//! lives in the wrong place; the fix is to move the shared piece down into its own lower module that
//! both sides use, never to hide the edge (a re-export or a differently spelled path is still an edge).
//!
//! The checker reads the workspace's `Cargo.toml` members, walks each crate's module tree from
//! `src/lib.rs` and `src/main.rs` (following `mod x;`), parses every file's `use` trees and qualified
//! paths, resolves each path to the deepest module file that exists (`a/b.rs`, `a/b/mod.rs`, or `a.rs`
//! when `b` is an item or an inline module), and reports every strongly connected component of more
//! than one file. Inline `#[cfg(test)] mod ... { ... }` blocks are skipped: a unit test's
//! `use super::*` is not part of the crate's structure.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fs;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------------
// Lexer: identifiers, `::` and single punctuation; comments, strings, chars and lifetimes dropped.

#[derive(Debug, Clone, PartialEq, Eq)]
enum Tok {
    Ident(String),
    PathSep,
    Punct(char),
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    line: usize,
}

fn is_ident_start(c: char) -> bool {
    c == '_' || c.is_alphabetic()
}

fn is_ident_continue(c: char) -> bool {
    c == '_' || c.is_alphanumeric()
}

fn lex(src: &str) -> Vec<Token> {
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

// ---------------------------------------------------------------------------------------------------
// Scanner: module declarations, `use` trees and qualified paths, each with the inline-module scope it
// appears in.

/// A `mod name;` or `mod name { .. }` declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
struct ModDecl {
    /// Inline modules around the declaration, outermost first.
    scope: Vec<String>,
    name: String,
    inline: bool,
}

/// One path named by the file: a leaf of a `use` tree or a qualified path in code.
#[derive(Debug, Clone, PartialEq, Eq)]
struct PathRef {
    scope: Vec<String>,
    segments: Vec<String>,
    line: usize,
    /// The name a `use` binds (`as` alias or last segment); `None` for globs and code paths.
    binds: Option<String>,
}

#[derive(Debug, Default)]
struct Scan {
    mods: Vec<ModDecl>,
    uses: Vec<PathRef>,
    code: Vec<PathRef>,
}

fn ident(tokens: &[Token], i: usize) -> Option<&str> {
    match tokens.get(i).map(|t| &t.tok) {
        Some(Tok::Ident(s)) => Some(s),
        _ => None,
    }
}

fn punct(tokens: &[Token], i: usize, c: char) -> bool {
    matches!(tokens.get(i).map(|t| &t.tok), Some(Tok::Punct(p)) if *p == c)
}

fn path_sep(tokens: &[Token], i: usize) -> bool {
    matches!(tokens.get(i).map(|t| &t.tok), Some(Tok::PathSep))
}

/// The index just past the group that opens at `i` (`open` .. matching `close`).
fn skip_group(tokens: &[Token], i: usize, open: char, close: char) -> usize {
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
fn opening(tokens: &[Token], k: usize, open: char, close: char) -> Option<usize> {
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

/// Whether the attributes and visibility just before the `mod` at `i` include `#[cfg(test)]` (or a
/// `cfg` that requires `test`).
fn cfg_test_before(tokens: &[Token], i: usize) -> bool {
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
fn parse_use_tree(tokens: &[Token], i: &mut usize, prefix: Vec<String>, out: &mut Vec<(Vec<String>, Option<String>)>) {
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

fn scan(tokens: &[Token]) -> Scan {
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

// ---------------------------------------------------------------------------------------------------
// Resolution: a path to the module file that defines what it names.

/// Module path (from the crate root) to the index of the file that holds it; inline modules map to
/// their enclosing file.
type Modules = HashMap<Vec<String>, usize>;

/// The deepest module a path names, or `None` when it leaves the crate (std, other crates, locals).
fn resolve(
    segments: &[String],
    current: &[String],
    modules: &Modules,
    aliases: &HashMap<String, Vec<String>>,
) -> Option<Vec<String>> {
    resolve_exact(segments, current, modules, aliases).map(|(m, _)| m)
}

/// [`resolve`], and whether the whole path is that module (no item or inline name cut off).
fn resolve_exact(
    segments: &[String],
    current: &[String],
    modules: &Modules,
    aliases: &HashMap<String, Vec<String>>,
) -> Option<(Vec<String>, bool)> {
    let (first, rest) = segments.split_first()?;
    let mut full: Vec<String> = match first.as_str() {
        "crate" => Vec::new(),
        "self" => current.to_vec(),
        "super" => {
            let mut up = current.to_vec();
            up.pop()?;
            up
        }
        name => {
            let mut child = current.to_vec();
            child.push(name.to_string());
            if modules.contains_key(&child) { child } else { aliases.get(name)?.clone() }
        }
    };
    for s in rest {
        match s.as_str() {
            "super" => {
                full.pop()?;
            }
            "self" => {}
            _ => full.push(s.clone()),
        }
    }
    let mut exact = true;
    while !modules.contains_key(&full) {
        full.pop()?;
        exact = false;
    }
    Some((full, exact))
}

// ---------------------------------------------------------------------------------------------------
// Crates: the module tree from each root, and the file graph.

struct SourceFile {
    /// Relative to the workspace root.
    path: PathBuf,
    module: Vec<String>,
    scan: Scan,
}

/// One compiled target: a library or binary root and every file its `mod` declarations reach.
struct Target {
    name: String,
    files: Vec<SourceFile>,
    modules: Modules,
}

fn load_target(root: &Path, entry: &Path, name: String) -> Target {
    let mut target = Target { name, files: Vec::new(), modules: HashMap::new() };
    walk(root, entry, Vec::new(), entry.parent().expect("src dir").to_path_buf(), &mut target);
    target
}

fn walk(root: &Path, file: &Path, module: Vec<String>, child_dir: PathBuf, target: &mut Target) {
    let text = fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let scan = scan(&lex(&text));
    let index = target.files.len();
    target.modules.insert(module.clone(), index);
    let mods = scan.mods.clone();
    let rel = file.strip_prefix(root).unwrap_or(file).to_path_buf();
    target.files.push(SourceFile { path: rel, module: module.clone(), scan });
    for decl in mods {
        let mut path = module.clone();
        path.extend(decl.scope.iter().cloned());
        path.push(decl.name.clone());
        if decl.inline {
            target.modules.insert(path, index);
            continue;
        }
        let mut dir = child_dir.clone();
        dir.extend(decl.scope.iter());
        let flat = dir.join(format!("{}.rs", decl.name));
        let nested = dir.join(&decl.name).join("mod.rs");
        if flat.is_file() {
            walk(root, &flat, path, dir.join(&decl.name), target);
        } else if nested.is_file() {
            walk(root, &nested, path, dir.join(&decl.name), target);
        }
    }
}

/// One edge of the file graph, with the first path that makes it (for the report).
#[derive(Debug, Clone)]
struct Edge {
    line: usize,
    path: String,
}

fn edges(target: &Target) -> BTreeMap<(usize, usize), Edge> {
    let mut out = BTreeMap::new();
    for (from, file) in target.files.iter().enumerate() {
        let current = |scope: &[String]| {
            let mut m = file.module.clone();
            m.extend(scope.iter().cloned());
            m
        };
        // Names a `use` binds to a whole module (`use crate::scene;`), for code paths like `scene::x::Y`.
        let mut aliases: HashMap<String, Vec<String>> = HashMap::new();
        for r in &file.scan.uses {
            let Some(name) = &r.binds else { continue };
            if let Some((m, true)) = resolve_exact(&r.segments, &current(&r.scope), &target.modules, &aliases) {
                aliases.insert(name.clone(), m);
            }
        }
        for r in file.scan.uses.iter().chain(&file.scan.code) {
            let Some(m) = resolve(&r.segments, &current(&r.scope), &target.modules, &aliases) else {
                continue;
            };
            let to = target.modules[&m];
            if to != from {
                out.entry((from, to)).or_insert_with(|| Edge { line: r.line, path: r.segments.join("::") });
            }
        }
    }
    out
}

/// Strongly connected components with more than one node (Tarjan), each sorted, in a stable order.
fn circles(nodes: usize, edges: &BTreeSet<(usize, usize)>) -> Vec<Vec<usize>> {
    struct State<'a> {
        adjacency: Vec<Vec<usize>>,
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: &'a mut Vec<Vec<usize>>,
    }
    fn connect(s: &mut State<'_>, v: usize) {
        s.index[v] = Some(s.next);
        s.low[v] = s.next;
        s.next += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for k in 0..s.adjacency[v].len() {
            let w = s.adjacency[v][k];
            match s.index[w] {
                None => {
                    connect(s, w);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort_unstable();
                s.out.push(component);
            }
        }
    }
    let mut adjacency = vec![Vec::new(); nodes];
    for &(a, b) in edges {
        adjacency[a].push(b);
    }
    let mut out = Vec::new();
    let mut state = State {
        adjacency,
        index: vec![None; nodes],
        low: vec![0; nodes],
        on_stack: vec![false; nodes],
        stack: Vec::new(),
        next: 0,
        out: &mut out,
    };
    for v in 0..nodes {
        if state.index[v].is_none() {
            connect(&mut state, v);
        }
    }
    out.sort();
    out
}

/// The workspace members listed in the root `Cargo.toml` (`dir/*` globs expanded).
fn workspace_members(root: &Path) -> Vec<PathBuf> {
    let manifest = fs::read_to_string(root.join("Cargo.toml")).expect("workspace Cargo.toml");
    let start = manifest.find("members").expect("workspace members");
    let open = start + manifest[start..].find('[').expect("members list");
    let close = open + manifest[open..].find(']').expect("members list end");
    let mut members = Vec::new();
    for entry in manifest[open + 1..close].split(',') {
        let name = entry.trim().trim_matches('"');
        if name.is_empty() {
            continue;
        }
        if let Some(parent) = name.strip_suffix("/*") {
            let mut dirs: Vec<PathBuf> = fs::read_dir(root.join(parent))
                .expect("member glob")
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.join("Cargo.toml").is_file())
                .collect();
            dirs.sort();
            members.extend(dirs);
        } else {
            members.push(root.join(name));
        }
    }
    members
}

fn workspace_root() -> PathBuf {
    let manifest_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest_dir
        .ancestors()
        .find(|d| fs::read_to_string(d.join("Cargo.toml")).is_ok_and(|t| t.contains("[workspace]")))
        .expect("workspace root")
        .to_path_buf()
}

/// Every circle in every target of the workspace, as report lines.
fn workspace_circles(root: &Path) -> Vec<String> {
    let mut report = Vec::new();
    for member in workspace_members(root) {
        let crate_name = member.file_name().unwrap_or_default().to_string_lossy().into_owned();
        for entry in ["lib.rs", "main.rs"] {
            let file = member.join("src").join(entry);
            if !file.is_file() {
                continue;
            }
            let target = load_target(root, &file, format!("{crate_name} ({entry})"));
            let graph = edges(&target);
            let nodes: BTreeSet<(usize, usize)> = graph.keys().copied().collect();
            for component in circles(target.files.len(), &nodes) {
                let names: Vec<String> =
                    component.iter().map(|&f| target.files[f].path.display().to_string()).collect();
                let mut text = format!("{}: {}", target.name, names.join(" <-> "));
                for (&(a, b), edge) in &graph {
                    if component.contains(&a) && component.contains(&b) {
                        text.push_str(&format!(
                            "\n    {}:{} -> {} (`{}`)",
                            target.files[a].path.display(),
                            edge.line,
                            target.files[b].path.display(),
                            edge.path
                        ));
                    }
                }
                report.push(text);
            }
        }
    }
    report
}

#[test]
fn no_import_circles() {
    let root = workspace_root();
    let report = workspace_circles(&root);
    assert!(
        report.is_empty(),
        "{} import circle(s); move the shared piece down into its own module that both sides use:\n\n{}\n",
        report.len(),
        report.join("\n\n")
    );
}

// ---------------------------------------------------------------------------------------------------
// The parser on small strings.

fn segs(path: &str) -> Vec<String> {
    path.split("::").map(str::to_string).collect()
}

fn use_paths(src: &str) -> Vec<String> {
    scan(&lex(src)).uses.iter().map(|r| r.segments.join("::")).collect()
}

fn code_paths(src: &str) -> Vec<String> {
    scan(&lex(src)).code.iter().map(|r| r.segments.join("::")).collect()
}

#[test]
fn lexer_drops_comments_strings_chars_and_lifetimes() {
    let src = r####"
        // use crate::a;
        /* use crate::b; /* nested */ use crate::c; */
        /// [`crate::d`]
        let s = "use crate::e;";
        let r = r#"crate::f::G "# ;
        let c = '{'; let q = '\''; let b = b'}';
        fn f<'a>(x: &'a str) {}
        use crate::g;
    "####;
    assert_eq!(use_paths(src), ["crate::g"]);
    assert!(code_paths(src).is_empty());
    let lines: Vec<usize> = scan(&lex(src)).uses.iter().map(|r| r.line).collect();
    assert_eq!(lines, [9]);
}

#[test]
fn use_trees_with_braces_globs_aliases_and_lines() {
    let src = "use super::{a::X, b::{Y, Z as W}, self};\nuse crate::c::\n    d::*;\npub use ::std::fmt;";
    assert_eq!(use_paths(src), ["super::a::X", "super::b::Y", "super::b::Z", "super", "crate::c::d", "::::std::fmt"]);
    let binds: Vec<Option<String>> = scan(&lex(src)).uses.iter().map(|r| r.binds.clone()).collect();
    assert_eq!(binds[2].as_deref(), Some("W"));
    assert_eq!(binds[4], None);
    let multi = "pub(crate) use self::{\n    leaf::Tri4,\n    build::{\n        build,\n    },\n};";
    assert_eq!(use_paths(multi), ["self::leaf::Tri4", "self::build::build"]);
}

#[test]
fn qualified_paths_in_code() {
    let src = "fn f() { let t = super::trace::Tree::new(x); crate::a::b(); Vec::<u8>::new(); $crate::m::z!(); }";
    assert_eq!(code_paths(src), ["super::trace::Tree::new", "crate::a::b", "Vec", "crate::m::z"]);
    // Visibility paths and attributes import nothing; `impl Trait + use<'a>` is not a `use`.
    let src = "#[cfg(feature = \"x\")] pub(in crate::a) fn g() -> impl Sized + use<'a> {}";
    assert!(code_paths(src).is_empty());
    assert!(use_paths(src).is_empty());
}

#[test]
fn inline_test_modules_are_skipped_and_inline_modules_scoped() {
    let src = "mod a;\n#[cfg(test)]\nmod tests {\n    use super::*;\n    use crate::x::Y;\n}\n\
               pub mod inner { use super::b::C; }\n#[cfg(test)] mod file_tests;";
    let s = scan(&lex(src));
    assert_eq!(s.uses.len(), 1);
    assert_eq!(s.uses[0].scope, ["inner"]);
    let mods: Vec<(&str, bool)> = s.mods.iter().map(|m| (m.name.as_str(), m.inline)).collect();
    assert_eq!(mods, [("a", false), ("inner", true), ("file_tests", false)]);
}

#[test]
fn resolution_finds_the_deepest_module_file() {
    let modules: Modules = [(vec![], 0), (segs("a"), 1), (segs("a::b"), 2), (segs("c"), 3)].into_iter().collect();
    let none = HashMap::new();
    let r = |p: &str, cur: &[&str]| {
        let cur: Vec<String> = cur.iter().map(|s| s.to_string()).collect();
        resolve(&segs(p), &cur, &modules, &none).map(|m| modules[&m])
    };
    assert_eq!(r("crate::a::b::Item", &[]), Some(2));
    assert_eq!(r("crate::a::Item::x", &[]), Some(1));
    assert_eq!(r("crate::Thing", &["c"]), Some(0));
    assert_eq!(r("super::Foo", &["a", "b"]), Some(1));
    assert_eq!(r("super::super::c::D", &["a", "b"]), Some(3));
    assert_eq!(r("self::b::E", &["a"]), Some(2));
    assert_eq!(r("b::E", &["a"]), Some(2));
    assert_eq!(r("std::fmt", &["a"]), None);
    let aliases: HashMap<String, Vec<String>> = [("m".to_string(), segs("a"))].into_iter().collect();
    let m = resolve(&segs("m::b::F"), &[], &modules, &aliases).map(|m| modules[&m]);
    assert_eq!(m, Some(2));
}

#[test]
fn tarjan_finds_only_real_circles() {
    let edges: BTreeSet<(usize, usize)> = [(0, 1), (1, 2), (2, 0), (2, 3), (3, 4), (5, 5)].into_iter().collect();
    assert_eq!(circles(6, &edges), [vec![0, 1, 2]]);
    let edges: BTreeSet<(usize, usize)> = [(0, 1), (1, 0), (2, 3), (3, 2)].into_iter().collect();
    assert_eq!(circles(4, &edges), [vec![0, 1], vec![2, 3]]);
}
