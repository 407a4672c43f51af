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

mod graph;
mod lex;
mod resolve;
mod scan;
mod tarjan;

use graph::{edges, load_target};
use lex::lex;
use resolve::{Modules, resolve};
use scan::scan;
use std::collections::{BTreeSet, HashMap};
use std::fs;
use std::path::{Path, PathBuf};
use tarjan::circles;

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
