//! A scene file's S-mesh keys (000 §7.1): per mesh `smesh = "coarse.obj"`, `smesh_target` or
//! `smesh_error`, and the scene-wide `[smesh]` table, checked into [`SMeshSource`]s.

use super::format::{MeshFile, SMeshFile};
use super::material::Material;
use super::smesh_plan::{SMeshSource, Simplify};
use crate::error::SceneError;
use crate::mesh::load_obj_with;
use crate::read::resolve_inside;
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};
use std::path::Path;

/// How far a given S mesh's box may reach beyond its mesh's, as a fraction of the mesh's diagonal.
const MAX_REACH: f32 = 0.25;

/// The simplification of `element` from its face count (`target`, key `target_key`) or error:
/// `None` when neither is given; an error naming the key when both are, or one is out of range.
fn simplify(
    path: &Path,
    element: &str,
    (target_key, target): (&str, Option<u32>),
    (error_key, error): (&str, Option<f32>),
) -> Result<Option<Simplify>, SceneError> {
    let (key, s) = match (target, error) {
        (None, None) => return Ok(None),
        (Some(_), Some(_)) => {
            return Err(SceneError::Invalid {
                path: path.to_path_buf(),
                element: element.to_string(),
                message: format!("give {target_key} or {error_key}, not both"),
            });
        }
        (Some(n), None) => (target_key, Simplify::Faces(n)),
        (None, Some(e)) => (error_key, Simplify::Error(e)),
    };
    s.checked().map(Some).map_err(|expected| SceneError::OutOfRange {
        path: path.to_path_buf(),
        element: format!("{element}.{key}"),
        expected,
    })
}

/// The scene-wide simplification of a scene file's `[smesh]` table.
pub(super) fn rest(path: &Path, table: Option<&SMeshFile>) -> Result<Option<Simplify>, SceneError> {
    match table {
        None => Ok(None),
        Some(t) => simplify(path, "smesh", ("target", t.target), ("error", t.error)),
    }
}

/// The S-mesh source of mesh `element` of the scene file `path` (in folder `dir`): its coarse S
/// mesh read from `m.smesh` and moved by `place` (the mesh's own transform), or its simplification;
/// `None` when it asks for neither. `fine` are its triangles (in the scene), `material` its
/// material and `material_name` the material's name in the file. The coarse mesh must lie over
/// the fine one ([`SceneError::SMeshFar`]); errors in its OBJ name its file and line.
pub(super) fn mesh_source(
    path: &Path,
    dir: &Path,
    allow_outside_paths: bool,
    element: &str,
    m: &MeshFile,
    (material, material_name): (&Material, &str),
    place: impl Fn(Vec3) -> Vec3,
    fine: &[Triangle],
) -> Result<Option<SMeshSource>, SceneError> {
    let simplified = simplify(path, element, ("smesh_target", m.smesh_target), ("smesh_error", m.smesh_error))?;
    if m.smesh.is_none() && simplified.is_none() {
        return Ok(None);
    }
    let key = if m.smesh.is_some() {
        "smesh"
    } else if m.smesh_target.is_some() {
        "smesh_target"
    } else {
        "smesh_error"
    };
    let at = format!("{element}.{key}");
    if !matches!(material, Material::Mirror { .. } | Material::Glass { .. }) {
        return Err(SceneError::SMeshNotSpecular {
            path: path.to_path_buf(),
            element: at,
            material: super::check::name(material_name),
        });
    }
    let Some(file) = &m.smesh else { return Ok(simplified.map(SMeshSource::Simplified)) };
    if simplified.is_some() {
        return Err(SceneError::Invalid {
            path: path.to_path_buf(),
            element: element.to_string(),
            message: "give smesh (a coarse mesh) or smesh_target / smesh_error (a simplification), not both".into(),
        });
    }
    let in_scene = |e| SceneError::InMesh { path: path.to_path_buf(), element: at.clone(), source: Box::new(e) };
    let (obj, inside) = resolve_inside(dir, file, allow_outside_paths).map_err(in_scene)?;
    let (mut mesh, _) = load_obj_with(&obj, inside).map_err(in_scene)?;
    for p in &mut mesh.positions {
        *p = place(*p);
    }
    let boxed = |points: &mut dyn Iterator<Item = Vec3>| points.fold(Aabb::EMPTY, |b, p| b.grow(p));
    let fine_box = boxed(&mut fine.iter().filter(|t| t.is_valid()).flat_map(|t| t.v));
    let used = boxed(&mut mesh.indices.iter().flatten().filter_map(|&i| mesh.positions.get(i as usize).copied()));
    if !fine_box.is_valid() {
        return Ok(None); // no triangle to cover
    }
    let size = fine_box.extent().length();
    let reach = (fine_box.min - used.min).max(used.max - fine_box.max).max(Vec3::ZERO).max_element();
    if !used.is_valid() || !(reach <= MAX_REACH * size) {
        return Err(SceneError::SMeshFar { path: path.to_path_buf(), element: at, distance: reach, size });
    }
    Ok(Some(SMeshSource::Given(mesh)))
}
