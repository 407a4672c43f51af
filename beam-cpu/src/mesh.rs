//! Triangle meshes from OBJ files (through tobj) and built-in procedural meshes.

use beam_math::Triangle;
use beam_math::glam::Vec3;
use std::path::Path;

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles as vertex indices.
    pub indices: Vec<[u32; 3]>,
}

impl Mesh {
    /// The triangles, one per index triple (degenerate ones included; the BVH counts and skips them).
    #[must_use]
    pub fn triangles(&self) -> Vec<Triangle> {
        self.indices.iter().map(|t| Triangle { v: t.map(|i| self.positions[i as usize]) }).collect()
    }

    /// Append another mesh.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.indices.extend(other.indices.iter().map(|t| t.map(|i| i + base)));
    }
}

/// Check the lines tobj reads (`v` and `f`) so that a malformed file is reported as
/// `file:line: what`, which tobj's own errors cannot say.
pub fn validate_obj(path: &Path, text: &str) -> Result<(), String> {
    let vertices = text.lines().filter(|l| l.split_whitespace().next() == Some("v")).count() as i64;
    for (n, line) in text.lines().enumerate() {
        let fail = |what: String| Err(format!("{}:{}: {what}", path.display(), n + 1));
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let coords: Vec<&str> = tokens.collect();
                if coords.len() < 3 || coords.iter().any(|c| c.parse::<f32>().is_err()) {
                    return fail(format!("a vertex needs three numbers: `{}`", line.trim()));
                }
            }
            Some("f") => {
                let corners: Vec<&str> = tokens.collect();
                if corners.len() < 3 {
                    return fail(format!("a face needs at least three vertices: `{}`", line.trim()));
                }
                for c in corners {
                    let i = c.split('/').next().unwrap_or("").parse::<i64>();
                    match i {
                        Ok(i) if i != 0 && i.abs() <= vertices => {}
                        _ => {
                            return fail(format!(
                                "face vertex `{c}` is not an index in 1..={vertices} (or −1..=−{vertices})"
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Load every object of an OBJ file into one mesh (faces triangulated). Errors name the file, and
/// the line for malformed vertices and faces.
pub fn load_obj(path: &Path) -> Result<Mesh, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    validate_obj(path, &text)?;
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    let (models, _) = tobj::load_obj(path, &options).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut mesh = Mesh::default();
    for m in &models {
        let p = &m.mesh.positions;
        if p.len() % 3 != 0 {
            return Err(format!("{}: object `{}` has a truncated position list", path.display(), m.name));
        }
        let part = Mesh {
            positions: p.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect(),
            indices: m.mesh.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        };
        let n = part.positions.len() as u32;
        if let Some(bad) = part.indices.iter().flatten().find(|&&i| i >= n) {
            return Err(format!("{}: object `{}` references vertex {} of {}", path.display(), m.name, bad + 1, n));
        }
        mesh.append(&part);
    }
    if mesh.indices.is_empty() {
        return Err(format!("{}: no triangles", path.display()));
    }
    Ok(mesh)
}

/// A UV sphere of `rings × segments` quads (two triangles each; the pole quads are degenerate and
/// stay in, as real meshes have them).
#[must_use]
pub fn sphere(center: Vec3, radius: f32, rings: u32, segments: u32) -> Mesh {
    let mut mesh = Mesh::default();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            mesh.positions
                .push(center + radius * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()));
        }
    }
    let w = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b, c, d) = (r * w + s, r * w + s + 1, (r + 1) * w + s, (r + 1) * w + s + 1);
            mesh.indices.push([a, b, c]);
            mesh.indices.push([b, d, c]);
        }
    }
    mesh
}

/// A parametric surface `f(u, v)`, `(u, v) ∈ [0, 1]²`, as an `nu × nv` grid of quads split into
/// triangles wound counter-clockwise around `∂f/∂u × ∂f/∂v`.
#[must_use]
pub fn parametric(nu: u32, nv: u32, f: impl Fn(f32, f32) -> Vec3) -> Mesh {
    let mut mesh = Mesh::default();
    for j in 0..=nv {
        for i in 0..=nu {
            mesh.positions.push(f(i as f32 / nu as f32, j as f32 / nv as f32));
        }
    }
    let w = nu + 1;
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (j * w + i, j * w + i + 1, (j + 1) * w + i, (j + 1) * w + i + 1);
            mesh.indices.push([a, b, d]);
            mesh.indices.push([a, d, c]);
        }
    }
    mesh
}

/// An axis-aligned box as 12 triangles (closed).
#[must_use]
pub fn cuboid(min: Vec3, max: Vec3) -> Mesh {
    let c = |i: u32| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    let positions = (0..8).map(c).collect();
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let indices = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    Mesh { positions, indices }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loads_obj_and_reports_errors_with_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let ok = dir.path().join("quad.obj");
        std::fs::write(&ok, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
        let m = load_obj(&ok).unwrap();
        assert_eq!(m.indices.len(), 2);
        let bad = dir.path().join("bad.obj");
        std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nf 1 2 9\n").unwrap();
        let e = load_obj(&bad).unwrap_err();
        assert!(e.contains("bad.obj"), "{e}");
        assert!(load_obj(&dir.path().join("missing.obj")).unwrap_err().contains("missing.obj"));
    }

    #[test]
    fn procedural_meshes() {
        let s = sphere(Vec3::ZERO, 1.0, 8, 16);
        assert_eq!(s.indices.len(), 8 * 16 * 2);
        assert!(s.triangles().iter().any(|t| !t.is_valid()), "pole triangles are degenerate");
        assert_eq!(cuboid(Vec3::ZERO, Vec3::ONE).triangles().iter().map(|t| t.area()).sum::<f32>(), 6.0);
    }
}
