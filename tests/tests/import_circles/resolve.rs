//! Resolution: a path to the module file that defines what it names.

use std::collections::HashMap;

/// Module path (from the crate root) to the index of the file that holds it; inline modules map to
/// their enclosing file.
pub(crate) type Modules = HashMap<Vec<String>, usize>;

/// The deepest module a path names, or `None` when it leaves the crate (std, other crates, locals).
pub(crate) fn resolve(
    segments: &[String],
    current: &[String],
    modules: &Modules,
    aliases: &HashMap<String, Vec<String>>,
) -> Option<Vec<String>> {
    resolve_exact(segments, current, modules, aliases).map(|(m, _)| m)
}

/// [`resolve`], and whether the whole path is that module (no item or inline name cut off).
pub(crate) fn resolve_exact(
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
