//! The OBJ parser: vertex positions (`v`) and faces (`f`), read in one pass over bytes already in
//! memory, every error naming `file:line`. Faces are triangulated in their plane (non-convex ones
//! too); lines (`l`) and points (`p`) are skipped and counted; everything else (normals, texture
//! coordinates, groups, materials: `mtllib` files are never opened) is ignored.

use super::indexed::Mesh;
use super::triangulate::triangulate;
use crate::error::SceneError;
use crate::read::quote;
use beam_math::glam::Vec3;
use std::path::Path;

/// Counts from parsing an OBJ file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ObjStats {
    /// Line (`l`) and point (`p`) elements skipped: they have no area to render.
    pub skipped_elements: usize,
}

/// A face as read: its line and its corners `corners[start..end]` (0-based vertex indices, checked
/// against the vertex count once the whole file is read).
struct Face {
    line: usize,
    start: usize,
    end: usize,
}

/// The mesh of the OBJ text `data` (from the file `path`, which errors name). `quote_lines`: whether
/// errors may quote the offending line (clipped to 80 characters).
pub fn parse_obj(path: &Path, data: &[u8], quote_lines: bool) -> Result<(Mesh, ObjStats), SceneError> {
    let text = String::from_utf8_lossy(data);
    let mut positions: Vec<Vec3> = Vec::new();
    let mut corners: Vec<i64> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    let mut stats = ObjStats::default();
    let mut joined = String::new();
    let mut first_line = 0;
    for (n, raw) in text.lines().enumerate() {
        // A trailing backslash continues the statement on the next line.
        if joined.is_empty() {
            first_line = n + 1;
        }
        if let Some(head) = raw.strip_suffix('\\') {
            joined.push_str(head);
            joined.push(' ');
            continue;
        }
        let statement;
        let line: &str = if joined.is_empty() {
            raw
        } else {
            joined.push_str(raw);
            statement = std::mem::take(&mut joined);
            &statement
        };
        let fail = |what: &str| {
            let quoted = if quote_lines { format!(": `{}`", quote(line)) } else { String::new() };
            Err(SceneError::Obj { path: path.to_path_buf(), line: first_line, message: format!("{what}{quoted}") })
        };
        // Comments run from `#` to the end of the line, after data too.
        let data = line.split_once('#').map_or(line, |(d, _)| d);
        let mut tokens = data.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let mut xyz = [0.0f32; 3];
                let mut count = 0;
                for t in tokens {
                    let Ok(x) = t.parse::<f32>() else {
                        return fail(&format!("vertex coordinate {} must be a number", count + 1));
                    };
                    if count < 3 {
                        xyz[count] = x;
                    }
                    count += 1;
                }
                // x y z, optionally w, or x y z r g b (vertex colours).
                if !matches!(count, 3 | 4 | 6 | 7) {
                    return fail(&format!(
                        "a vertex needs three numbers (x y z, then optionally w or r g b), not {count}"
                    ));
                }
                positions.push(Vec3::from_array(xyz));
            }
            Some("f") => {
                let start = corners.len();
                for (k, c) in tokens.enumerate() {
                    let parts: Vec<&str> = c.split('/').collect();
                    let integer = |s: &str| s.parse::<i64>().is_ok_and(|i| i != 0);
                    let well_formed = match parts[..] {
                        [_] => true,
                        [_, t] => integer(t),
                        [_, t, n] => (t.is_empty() || integer(t)) && integer(n),
                        _ => false,
                    };
                    if !well_formed {
                        return fail(&format!("face corner {} is not v, v/vt, v//vn or v/vt/vn", k + 1));
                    }
                    let index = match parts[0].parse::<i64>() {
                        Ok(i) if i > 0 => i - 1,
                        // Negative indices count back from the last vertex read so far.
                        Ok(i) if i < 0 && i.unsigned_abs() <= positions.len() as u64 => positions.len() as i64 + i,
                        _ => {
                            return fail(&format!(
                                "face corner {} is not a vertex index (1 to N, or −1 to −{} counting back)",
                                k + 1,
                                positions.len()
                            ));
                        }
                    };
                    corners.push(index);
                }
                if corners.len() - start < 3 {
                    return fail("a face needs at least three corners");
                }
                faces.push(Face { line: first_line, start, end: corners.len() });
            }
            Some("l" | "p") => stats.skipped_elements += 1,
            _ => {}
        }
    }
    let mut indices = Vec::new();
    let mut face = Vec::new();
    for f in &faces {
        face.clear();
        for &i in &corners[f.start..f.end] {
            if i >= positions.len() as i64 {
                return Err(SceneError::Obj {
                    path: path.to_path_buf(),
                    line: f.line,
                    message: format!("face corner {} is past the last vertex ({})", i + 1, positions.len()),
                });
            }
            face.push(i as u32);
        }
        triangulate(&positions, &face, &mut indices).map_err(|source| SceneError::Face {
            path: path.to_path_buf(),
            line: f.line,
            source,
        })?;
    }
    Ok((Mesh { positions, indices }, stats))
}
