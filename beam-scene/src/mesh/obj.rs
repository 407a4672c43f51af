//! The OBJ parser: vertex positions (`v`), faces (`f`) and the names of their materials (`mtllib`,
//! `usemtl`: the libraries are read by [`super::mtl`]), read in one pass over bytes already in
//! memory, every error naming `file:line`. Faces are triangulated in their plane (non-convex ones
//! too); lines (`l`) and points (`p`) are skipped and counted; everything else (normals, texture
//! coordinates, groups) is ignored.

use super::indexed::Mesh;
use super::triangulate::triangulate;
use crate::error::SceneError;
use crate::read::quote;
use beam_math::glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::path::Path;

/// Counts and material names from parsing an OBJ file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjStats {
    /// Line (`l`) and point (`p`) elements skipped: they have no area to render.
    pub skipped_elements: usize,
    /// The material libraries it names (`mtllib`), with the line of each.
    pub libraries: Vec<(usize, String)>,
    /// The materials its faces use (`usemtl`), in the order of their first use.
    pub materials: Vec<String>,
    /// Per triangle of the mesh, its material: `0` where no `usemtl` came before its face, else
    /// `1 +` its index in `materials`.
    pub triangle_materials: Vec<u32>,
    /// Per triangle of the mesh, its corners' texture coordinates (`vt`, with `v` turned to run
    /// down the image as textures are read here; zeros for a face without them); empty when no
    /// face has any.
    pub triangle_uvs: Vec<[Vec2; 3]>,
    /// Per triangle of the mesh, its corners' unit normals (`vn`; zeros for a face without them);
    /// empty when no face has any.
    pub triangle_normals: Vec<[Vec3; 3]>,
}

/// The index a face corner's word `part` (after its first or second slash) gives into a list of
/// `len` values read so far: −1 for none, 0-based for `1` to `N` or `−1` to `−len` counting back;
/// `None` when it is not such an index (a positive one past the end is checked at the end).
fn attribute_index(part: Option<&str>, len: usize) -> Option<i64> {
    match part.filter(|t| !t.is_empty()).map(str::parse::<i64>) {
        None => Some(-1),
        Some(Ok(i)) if i > 0 => Some(i - 1),
        Some(Ok(i)) if i < 0 && i.unsigned_abs() <= len as u64 => Some(len as i64 + i),
        Some(_) => None,
    }
}

/// The triangles one face was cut into, to give their corners the face's per-corner values.
struct Corners<'a> {
    path: &'a Path,
    /// The face's vertices, and its line.
    face: &'a [u32],
    line: usize,
    /// Its first corner's index in the per-corner lists.
    start: usize,
    triangles: &'a [[u32; 3]],
}

impl Corners<'_> {
    /// Push onto `out` each triangle's corner values: a triangle corner is a vertex of the face,
    /// whose value is that of the face's first corner at the vertex (`indices` into `values`, −1:
    /// the default).
    fn values<T: Copy + Default>(
        &self,
        indices: &[i64],
        values: &[T],
        what: &str,
        out: &mut Vec<[T; 3]>,
    ) -> Result<(), SceneError> {
        let value = |v: u32| match self.face.iter().position(|&w| w == v).map_or(-1, |k| indices[self.start + k]) {
            -1 => Ok(T::default()),
            k if k < values.len() as i64 => Ok(values[k as usize]),
            k => Err(SceneError::Obj {
                path: self.path.to_path_buf(),
                line: self.line,
                message: format!("{what} {} is past the last ({})", k + 1, values.len()),
            }),
        };
        for t in self.triangles {
            out.push([value(t[0])?, value(t[1])?, value(t[2])?]);
        }
        Ok(())
    }
}

/// Most materials an OBJ file may use (`usemtl` names).
const MAX_MATERIALS: usize = 65_536;

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
    let (mut uvs, mut normals): (Vec<Vec2>, Vec<Vec3>) = (Vec::new(), Vec::new());
    // Per corner, the index of its texture coordinates and of its normal (−1: none).
    let (mut corner_uvs, mut corner_normals): (Vec<i64>, Vec<i64>) = (Vec::new(), Vec::new());
    let mut faces: Vec<Face> = Vec::new();
    let mut stats = ObjStats::default();
    // Per face, its material (as in `triangle_materials`).
    let mut face_materials: Vec<u32> = Vec::new();
    let mut current = 0u32;
    let mut slots: HashMap<String, u32> = HashMap::new();
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
            Some("vt") => {
                // Non-finite coordinates (written for degenerate faces) read texel 0 of a texture.
                let mut uv = Vec::with_capacity(3);
                for t in tokens {
                    match t.parse::<f32>() {
                        Ok(x) if uv.len() < 3 => uv.push(x),
                        Ok(_) => return fail("texture coordinates are u, then optionally v and w"),
                        Err(_) => return fail(&format!("texture coordinate {} must be a number", uv.len() + 1)),
                    }
                }
                let Some(&u) = uv.first() else { return fail("texture coordinates need at least u") };
                let uv = [u, uv.get(1).copied().unwrap_or(0.0)];
                uvs.push(Vec2::new(uv[0], 1.0 - uv[1]));
            }
            Some("vn") => {
                // Some tools write `nan` for the normal of a degenerate face: such a normal (and a
                // zero one) is no normal, and its corners keep their face's own.
                let n: Vec<f32> = tokens.map(|t| t.parse::<f32>().ok()).collect::<Option<_>>().unwrap_or_default();
                let [x, y, z] = n[..] else { return fail("a normal needs three numbers") };
                normals.push(Vec3::new(x, y, z).normalize_or_zero());
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
                    for (slot, list, len, what) in [
                        (1, &mut corner_uvs, uvs.len(), "texture coordinates"),
                        (2, &mut corner_normals, normals.len(), "normal"),
                    ] {
                        let Some(i) = attribute_index(parts.get(slot).copied(), len) else {
                            return fail(&format!(
                                "face corner {}'s {what} is not an index (1 to N, or −1 to −{len} counting back)",
                                k + 1
                            ));
                        };
                        list.push(i);
                    }
                }
                if corners.len() - start < 3 {
                    return fail("a face needs at least three corners");
                }
                faces.push(Face { line: first_line, start, end: corners.len() });
                face_materials.push(current);
            }
            Some("l" | "p") => stats.skipped_elements += 1,
            Some("mtllib") => stats.libraries.extend(tokens.map(|name| (first_line, name.to_string()))),
            Some("usemtl") => {
                // The name is the rest of the statement (some exporters write names with spaces).
                let name = data.trim_start()["usemtl".len()..].trim();
                current = match slots.get(name) {
                    Some(&slot) => slot,
                    None if stats.materials.len() < MAX_MATERIALS => {
                        stats.materials.push(name.to_string());
                        slots.insert(name.to_string(), stats.materials.len() as u32);
                        stats.materials.len() as u32
                    }
                    None => return fail(&format!("more than {MAX_MATERIALS} materials")),
                };
            }
            _ => {}
        }
    }
    let mut indices = Vec::new();
    let mut face = Vec::new();
    let textured = corner_uvs.iter().any(|&t| t >= 0);
    let smooth = corner_normals.iter().any(|&t| t >= 0);
    for (f, &material) in faces.iter().zip(&face_materials) {
        let first = indices.len();
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
        stats.triangle_materials.resize(indices.len(), material);
        let at = Corners { path, face: &face, line: f.line, start: f.start, triangles: &indices[first..] };
        if textured {
            at.values(&corner_uvs, &uvs, "texture coordinates", &mut stats.triangle_uvs)?;
        }
        if smooth {
            at.values(&corner_normals, &normals, "normal", &mut stats.triangle_normals)?;
        }
    }
    Ok((Mesh { positions, indices }, stats))
}
