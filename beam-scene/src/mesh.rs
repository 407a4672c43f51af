//! Triangle meshes from OBJ files (`obj`, their materials' libraries `mtl`) and built-in procedural
//! meshes.

mod indexed;
pub(crate) mod limits;
mod mtl;
mod obj;
mod triangulate;

pub use indexed::Mesh;
pub use limits::MAX_NONCONVEX_CORNERS;
pub use mtl::{DEFAULT_KD, MtlBump, MtlMaterial, parse_mtl};
pub use obj::{ObjStats, parse_obj};
pub use triangulate::triangulate;

use crate::error::SceneError;
use beam_math::glam::Vec3;
use std::path::Path;

/// Load every object of an OBJ file into one mesh (faces triangulated in their plane). The file is
/// read once, bounded by [`MAX_MESH_BYTES`](crate::read::MAX_MESH_BYTES), and must be a regular
/// file. Errors name the file, and `file:line` for malformed lines, quoting the line.
pub fn load_obj(path: &Path) -> Result<Mesh, SceneError> {
    load_obj_with(path, true).map(|(mesh, _)| mesh)
}

/// [`load_obj`], with the counts of skipped elements; `quote_lines`: whether errors may quote a
/// line of the file (not for files outside a scene's folder).
pub fn load_obj_with(path: &Path, quote_lines: bool) -> Result<(Mesh, ObjStats), SceneError> {
    let data = crate::read::read_bounded(path, crate::read::MAX_MESH_BYTES)?;
    let (mesh, stats) = parse_obj(path, &data, quote_lines)?;
    if mesh.indices.is_empty() {
        return Err(SceneError::NoTriangles { path: path.to_path_buf(), skipped: stats.skipped_elements });
    }
    Ok((mesh, stats))
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
        assert!(matches!(&e, SceneError::Obj { path, line: 3, .. } if *path == bad), "{e:?}");
        assert!(e.to_string().contains("bad.obj"), "{e}");
        assert!(load_obj(&dir.path().join("missing.obj")).unwrap_err().to_string().contains("missing.obj"));
    }

    #[test]
    fn procedural_meshes() {
        let s = sphere(Vec3::ZERO, 1.0, 8, 16);
        assert_eq!(s.indices.len(), 8 * 16 * 2);
        assert!(s.triangles().iter().any(|t| !t.is_valid()), "pole triangles are degenerate");
        assert_eq!(cuboid(Vec3::ZERO, Vec3::ONE).triangles().iter().map(|t| t.area()).sum::<f32>(), 6.0);
    }
}
