//! The `// #import` lines of the WGSL files: a file names each library file it uses on a line of
//! its own, `// #import lib/trace.wgsl` (a comment, so the file stays plain WGSL), with the path
//! relative to `beam-gpu/shaders/`. [`resolve`] follows them transitively: every file once, each
//! after the files it imports, and a cycle an error.

use crate::GpuError;

/// What an import line starts with (after its indentation), before the imported file's name.
pub(crate) const IMPORT: &str = "// #import ";

/// The files `text` imports, in the order of its import lines.
pub(crate) fn imports(text: &str) -> impl Iterator<Item = &str> {
    text.lines().filter_map(|line| line.trim_start().strip_prefix(IMPORT)).map(str::trim)
}

/// The files `root` (named `file`) needs, `(name, text)`: what its imports bring in, transitively,
/// each file once and after the files it imports (depth first, in the order of the import lines),
/// then `root` itself last. `lookup` finds an importable file's text by name.
pub(crate) fn resolve<'a>(
    file: &str,
    root: &'a str,
    lookup: impl Fn(&str) -> Option<&'a str>,
) -> Result<Vec<(String, &'a str)>, GpuError> {
    let mut out = Vec::new();
    visit(file, root, &lookup, &mut Vec::new(), &mut out)?;
    Ok(out)
}

/// Appends `file`'s imports not yet in `out`, then `file`; `path` is the chain of files being
/// visited (a file met again on it closes a cycle).
fn visit<'a>(
    file: &str,
    text: &'a str,
    lookup: &impl Fn(&str) -> Option<&'a str>,
    path: &mut Vec<String>,
    out: &mut Vec<(String, &'a str)>,
) -> Result<(), GpuError> {
    path.push(file.to_string());
    for import in imports(text) {
        if let Some(at) = path.iter().position(|p| p == import) {
            let cycle = path[at..].iter().cloned().chain([import.to_string()]).collect();
            return Err(GpuError::ImportCycle { cycle });
        }
        if out.iter().any(|(name, _)| name == import) {
            continue;
        }
        let found = lookup(import)
            .ok_or_else(|| GpuError::UnknownImport { file: file.to_string(), import: import.to_string() })?;
        visit(import, found, lookup, path, out)?;
    }
    path.pop();
    out.push((file.to_string(), text));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lookup<'a>(files: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<&'a str> {
        move |name| files.iter().find(|(n, _)| *n == name).map(|(_, text)| *text)
    }

    fn names<'a>(files: &'a [(String, &str)]) -> Vec<&'a str> {
        files.iter().map(|(n, _)| n.as_str()).collect()
    }

    #[test]
    fn a_transitive_import_comes_once_before_its_importers() {
        let files = [
            ("lib/a.wgsl", "// #import lib/c.wgsl\nfn a() {}\n"),
            ("lib/b.wgsl", "  // #import lib/c.wgsl\n// #import lib/a.wgsl\nfn b() {}\n"),
            ("lib/c.wgsl", "fn c() {}\n"),
            ("lib/unused.wgsl", "fn unused() {}\n"),
        ];
        let root =
            "// #import lib/a.wgsl\n// #import lib/b.wgsl\n// #import lib/c.wgsl\n// not #import lib/unused.wgsl\n";
        let got = resolve("s.wgsl", root, lookup(&files)).unwrap();
        assert_eq!(names(&got), ["lib/c.wgsl", "lib/a.wgsl", "lib/b.wgsl", "s.wgsl"]);
        assert_eq!(got[3].1, root);
        assert_eq!(names(&resolve("plain.wgsl", "fn main() {}", lookup(&files)).unwrap()), ["plain.wgsl"]);
    }

    #[test]
    fn a_cycle_and_an_unknown_import_are_errors() {
        let files = [
            ("lib/a.wgsl", "// #import lib/b.wgsl\n"),
            ("lib/b.wgsl", "// #import lib/c.wgsl\n"),
            ("lib/c.wgsl", "// #import lib/a.wgsl\n"),
            ("lib/self.wgsl", "// #import lib/self.wgsl\n"),
            ("lib/missing.wgsl", "// #import lib/nowhere.wgsl\n"),
        ];
        let e = resolve("s.wgsl", "// #import lib/a.wgsl\n", lookup(&files)).unwrap_err();
        assert!(
            matches!(&e, GpuError::ImportCycle { cycle } if cycle == &["lib/a.wgsl", "lib/b.wgsl", "lib/c.wgsl", "lib/a.wgsl"]),
            "{e:?}"
        );
        assert_eq!(e.to_string(), "shader import cycle: lib/a.wgsl → lib/b.wgsl → lib/c.wgsl → lib/a.wgsl");
        let e = resolve("s.wgsl", "// #import lib/self.wgsl\n", lookup(&files)).unwrap_err();
        assert!(matches!(&e, GpuError::ImportCycle { cycle } if cycle == &["lib/self.wgsl", "lib/self.wgsl"]), "{e:?}");
        let e = resolve("s.wgsl", "// #import lib/missing.wgsl\n", lookup(&files)).unwrap_err();
        assert_eq!(e.to_string(), "lib/missing.wgsl: imports `lib/nowhere.wgsl`, which is not a shader library file");
    }
}
