//! Crates: the module tree from each root, and the file graph between its files.

use super::lex::lex;
use super::resolve::{Modules, resolve, resolve_exact};
use super::scan::{Scan, scan};
use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::path::{Path, PathBuf};

pub(crate) struct SourceFile {
    /// Relative to the workspace root.
    pub(crate) path: PathBuf,
    pub(crate) module: Vec<String>,
    pub(crate) scan: Scan,
}

/// One compiled target: a library or binary root and every file its `mod` declarations reach.
pub(crate) struct Target {
    pub(crate) name: String,
    pub(crate) files: Vec<SourceFile>,
    pub(crate) modules: Modules,
}

pub(crate) fn load_target(root: &Path, entry: &Path, name: String) -> Target {
    let mut target = Target { name, files: Vec::new(), modules: HashMap::new() };
    walk(root, entry, Vec::new(), entry.parent().expect("src dir").to_path_buf(), &mut target);
    target
}

pub(crate) fn walk(root: &Path, file: &Path, module: Vec<String>, child_dir: PathBuf, target: &mut Target) {
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
pub(crate) struct Edge {
    pub(crate) line: usize,
    pub(crate) path: String,
}

pub(crate) fn edges(target: &Target) -> BTreeMap<(usize, usize), Edge> {
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
