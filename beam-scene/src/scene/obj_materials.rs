//! A bare OBJ file's materials, from the MTL libraries it names (`mtllib`, read by
//! [`parse_mtl`]) for the names its faces use (`usemtl`):
//! - `Ke` above zero → [`Material::Emissive`] (each of its triangles also a triangle light);
//! - `Kd` black with `Ks` above zero (a polished box) → [`Material::Glossy`] of albedo `Ks`, its
//!   Phong exponent `Ns` taken as a Gaussian lobe about the mirror direction of variance `1/Ns`
//!   (facets of variance `1 / (4 Ns)`; below `Ns = 1`, diffuse of albedo `Ks`);
//! - otherwise → [`Material::Diffuse`] of albedo `Kd` (channels above 1 clamped).
//!
//! Faces before any `usemtl`, names no library defines and a library that is missing get the bare
//! file's grey; texture maps, dissolve and the specular part of a diffuse material are not read.
//! Each of these is counted in one notice.

use super::load_options::LoadOptions;
use super::material::Material;
use crate::error::SceneError;
use crate::mesh::{DEFAULT_KD, MtlMaterial, ObjStats, parse_mtl};
use crate::read::{MAX_SCENE_BYTES, read_bounded, resolve_inside};
use beam_math::glam::Vec3;
use std::collections::HashMap;
use std::path::Path;

/// The materials of an OBJ file: per slot of [`ObjStats::triangle_materials`], and the notices of
/// what was not used, as `(what, count)`.
pub(super) struct ObjMaterials {
    pub(super) materials: Vec<Material>,
    pub(super) notices: Vec<(&'static str, usize)>,
}

/// The materials of the OBJ file `path`, whose parse gave `stats`; its libraries lie in its folder
/// unless `options` allows others.
pub(super) fn obj_materials(path: &Path, stats: &ObjStats, options: &LoadOptions) -> Result<ObjMaterials, SceneError> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut defined: HashMap<String, MtlMaterial> = HashMap::new();
    let mut missing_libraries = 0;
    for (line, name) in &stats.libraries {
        let in_obj = |e| SceneError::InMesh {
            path: path.to_path_buf(),
            element: format!("mtllib on line {line}"),
            source: Box::new(e),
        };
        let read = resolve_inside(dir, name, options.allow_outside_paths)
            .and_then(|(file, inside)| Ok((read_bounded(&file, MAX_SCENE_BYTES)?, file, inside)));
        let (data, file, inside) = match read {
            Ok(read) => read,
            Err(SceneError::Read { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
                missing_libraries += 1;
                continue;
            }
            Err(e) => return Err(in_obj(e)),
        };
        for m in parse_mtl(&file, &data, inside).map_err(in_obj)? {
            defined.insert(m.name.clone(), m);
        }
    }
    let grey = Material::Diffuse { albedo: Vec3::splat(DEFAULT_KD) };
    let mut materials = vec![grey];
    let (mut undefined, mut maps, mut dissolving, mut specular, mut clamped) = (0, 0, 0, 0, 0);
    for name in &stats.materials {
        let Some(m) = defined.get(name) else {
            undefined += 1;
            materials.push(grey);
            continue;
        };
        maps += m.maps;
        dissolving += usize::from(m.dissolves);
        let material = if m.ke.max_element() > 0.0 {
            Material::Emissive { radiance: m.ke }
        } else if m.kd.max_element() == 0.0 && m.ks.max_element() > 0.0 {
            clamped += usize::from(m.ks.max_element() > 1.0);
            let albedo = m.ks.min(Vec3::ONE);
            if m.ns >= 1.0 { Material::Glossy { albedo, variance: 0.25 / m.ns } } else { Material::Diffuse { albedo } }
        } else {
            specular += usize::from(m.ks.max_element() > 0.0);
            clamped += usize::from(m.kd.max_element() > 1.0);
            Material::Diffuse { albedo: m.kd.min(Vec3::ONE) }
        };
        materials.push(material);
    }
    let notices = vec![
        ("OBJ material librar(ies) not found: their materials drawn grey", missing_libraries),
        ("OBJ material name(s) (usemtl) in no library: drawn grey", undefined),
        ("OBJ material texture map(s) not read: the flat colours (Kd) are used", maps),
        ("partly transparent OBJ material(s) (d, Tr) drawn opaque", dissolving),
        ("specular part(s) (Ks) of diffuse OBJ materials not drawn", specular),
        ("OBJ material colour(s) above 1 clamped to 1", clamped),
    ];
    Ok(ObjMaterials { materials, notices })
}
