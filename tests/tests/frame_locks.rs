//! No lock on a frame's path: the frame's state is a value handed from stage to stage
//! (`KeptFrame`, the GPU's `ShadeChecks`), what a renderer keeps across frames sits behind
//! `&mut self`, and the device's buffer pools are lock-free queues (`beam-gpu/src/pool.rs`). A
//! `Mutex` or `RwLock` in these sources would hide state where the next reader cannot follow it
//! (docs/ARCHITECTURE.md, "Rules the layout keeps").

use std::fs;
use std::path::{Path, PathBuf};

/// The sources a frame of every method runs through on the GPU, and the frame drivers.
const FRAME_PATH: [&str; 3] = ["beam-gpu/src", "beam-render/src", "beam-cpu/src/nonlinear"];

/// The `.rs` files under `dir`, recursively.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())).flatten() {
        let path = entry.path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Lines of `text` (1-based) that name a lock in code, comments left out.
fn lock_lines(text: &str) -> Vec<(usize, String)> {
    let code = |line: &str| line.split("//").next().unwrap_or_default().to_string();
    text.lines()
        .enumerate()
        .filter(|(_, line)| ["Mutex", "RwLock"].iter().any(|lock| code(line).contains(lock)))
        .map(|(i, line)| (i + 1, line.trim().to_string()))
        .collect()
}

#[test]
fn no_lock_on_the_frame_path() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the workspace root");
    let mut files = Vec::new();
    for dir in FRAME_PATH {
        sources(&root.join(dir), &mut files);
    }
    assert!(files.len() > 50, "only {} sources found under {FRAME_PATH:?}", files.len());
    let found: Vec<String> = files
        .iter()
        .flat_map(|f| {
            let text = fs::read_to_string(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            let name = f.strip_prefix(root).unwrap_or(f).display().to_string();
            lock_lines(&text).into_iter().map(move |(n, line)| format!("{name}:{n}: {line}"))
        })
        .collect();
    assert!(found.is_empty(), "locks on the frame path:\n{}", found.join("\n"));
}

#[test]
fn a_lock_in_code_is_found_and_one_in_a_comment_is_not() {
    let text = "use std::sync::Mutex;\n// a Mutex here is prose\nlet x = 1; // RwLock in a comment\n";
    assert_eq!(lock_lines(text), vec![(1, "use std::sync::Mutex;".to_string())]);
}
