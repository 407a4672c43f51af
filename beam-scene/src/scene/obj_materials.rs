//! A bare OBJ file's materials, from the MTL libraries it names (`mtllib`, read by
//! [`parse_mtl`]) for the names its faces use (`usemtl`):
//! - `Ke` above zero → [`Material::Emissive`] (each of its triangles also a triangle light);
//! - `Kd` black with `Ks` above zero (a polished box) → [`Material::Glossy`] of albedo `Ks`, its
//!   Phong exponent `Ns` taken as a Gaussian lobe about the mirror direction of variance `1/Ns`
//!   (facets of variance `1 / (4 Ns)`; below `Ns = 1`, diffuse of albedo `Ks`);
//! - otherwise → [`Material::Diffuse`] of albedo `Kd` (channels above 1 clamped), or with a
//!   `map_Kd` texture (PNG, JPEG, TGA or BMP, beside its library; `\` read as `/`) that texture
//!   instead of `Kd`, as Blender imports it, read at the faces' `vt` coordinates (repeating,
//!   bilinear);
//! - a diffuse or glossy material's bump map (`bump`, `map_Bump`: heights, turned into normals with
//!   its `-bm` multiplier, or a normal map as Blender writes them) or normal map (`norm`) bends its
//!   shading normals as a glTF normal texture does ([`bump`](super::bump));
//! - a diffuse or glossy material's alpha map (`map_d`: the image's alpha, or its grey level where
//!   it has no alpha, as Blender reads it) cuts it out where that is below ½, as a glTF `MASK`
//!   cut-out (leaves, fences).
//!
//! Faces before any `usemtl`, names no library defines and a library that is missing get the bare
//! file's grey; a texture that is missing or in another format leaves `Kd` (or the faces flat);
//! the other texture maps, map options other than `-bm`, a constant dissolve (`d`, `Tr`) and the
//! specular part of a diffuse material are not read. Each of these is counted in one notice.

use super::bump::{height_to_normals, is_normal_map};
use super::image_file::{MTL_IMAGES, decode_image};
use super::load_options::LoadOptions;
use super::material::Material;
use super::surface::{AlphaCut, MaterialMaps, NormalMap, TextureRef};
use super::texture::{Filter, Texture, Wrap};
use crate::error::SceneError;
use crate::mesh::{DEFAULT_KD, MtlMaterial, ObjStats, parse_mtl};
use crate::read::{MAX_MESH_BYTES, MAX_SCENE_BYTES, clip, read_bounded, resolve_inside, visible};
use beam_math::glam::{Affine2, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The materials of an OBJ file: per slot of [`ObjStats::triangle_materials`], with their textures
/// (no maps when none has one), and the notices of what was not used, as `(what, count)`.
pub(super) struct ObjMaterials {
    pub(super) materials: Vec<Material>,
    pub(super) maps: Vec<MaterialMaps>,
    pub(super) textures: Vec<Texture>,
    pub(super) notices: Vec<(&'static str, usize)>,
}

/// The materials of the OBJ file `path`, whose parse gave `stats`; its libraries and their
/// textures lie in its folder unless `options` allows others.
pub(super) fn obj_materials(path: &Path, stats: &ObjStats, options: &LoadOptions) -> Result<ObjMaterials, SceneError> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    // Each material with the folder of its library.
    let mut defined: HashMap<String, (MtlMaterial, PathBuf)> = HashMap::new();
    let mut missing_libraries = 0;
    for (line, name) in &stats.libraries {
        let in_obj = |e| SceneError::InMesh {
            path: path.to_path_buf(),
            element: format!("mtllib on line {line}"),
            source: Box::new(e),
        };
        let Some((data, file, inside)) = read_optional(dir, name, MAX_SCENE_BYTES, options).map_err(in_obj)? else {
            missing_libraries += 1;
            continue;
        };
        let folder = file.parent().map_or_else(|| dir.to_path_buf(), Path::to_path_buf);
        for m in parse_mtl(&file, &data, inside).map_err(in_obj)? {
            defined.insert(m.name.clone(), (m, folder.clone()));
        }
    }
    let grey = Material::Diffuse { albedo: Vec3::splat(DEFAULT_KD) };
    let mut materials = vec![grey];
    let mut maps = vec![MaterialMaps::default()];
    let mut textures = Textures::default();
    let (mut undefined, mut other_maps, mut dissolving, mut specular, mut clamped) = (0, 0, 0, 0, 0);
    for name in &stats.materials {
        let (material, base_color) = match defined.get(name) {
            None => {
                undefined += 1;
                (grey, None)
            }
            Some((m, _)) if m.ke.max_element() > 0.0 => (Material::Emissive { radiance: m.ke }, None),
            Some((m, _)) if m.kd.max_element() == 0.0 && m.ks.max_element() > 0.0 => {
                clamped += usize::from(m.ks.max_element() > 1.0);
                let albedo = m.ks.min(Vec3::ONE);
                let polished = m.ns >= 1.0;
                (
                    if polished {
                        Material::Glossy { albedo, variance: 0.25 / m.ns }
                    } else {
                        Material::Diffuse { albedo }
                    },
                    None,
                )
            }
            Some((m, folder)) => {
                specular += usize::from(m.ks.max_element() > 0.0);
                let texture = match &m.map_kd {
                    Some((file, with_options)) => {
                        let error = in_material(path, name, "map_Kd");
                        textures.read_map(folder, (file, *with_options), Kind::Colour, (stats, options), error)?
                    }
                    None => None,
                };
                clamped += usize::from(texture.is_none() && m.kd.max_element() > 1.0);
                let albedo = if texture.is_some() { Vec3::ONE } else { m.kd.min(Vec3::ONE) };
                let base_color = texture.map(|(texture, _)| texture_ref(texture));
                (Material::Diffuse { albedo }, base_color)
            }
        };
        let (mut normal, mut alpha) = (None, None);
        if let Some((m, folder)) = defined.get(name) {
            other_maps += m.maps;
            dissolving += usize::from(m.dissolves);
            let reflecting = matches!(material, Material::Diffuse { .. } | Material::Glossy { .. });
            let read = (stats, options);
            match &m.bump {
                Some(bump) if reflecting => {
                    let kind = Kind::Bump { normal: bump.normal, scale: bump.scale };
                    let error = in_material(path, name, "bump map");
                    let texture = textures.read_map(folder, (&bump.file, bump.options), kind, read, error)?;
                    // A normal map's tilt is scaled by `-bm`; heights were, when made normals.
                    normal = texture.map(|(texture, is_normal)| NormalMap {
                        texture: texture_ref(texture),
                        scale: if is_normal { bump.scale } else { 1.0 },
                    });
                }
                Some(_) => other_maps += 1,
                None => {}
            }
            match &m.map_d {
                Some((file, with_options)) if reflecting => {
                    let error = in_material(path, name, "map_d");
                    let texture = textures.read_map(folder, (file, *with_options), Kind::Alpha, read, error)?;
                    let texture = texture.map(|(texture, _)| texture_ref(texture));
                    alpha = texture.map(|t| AlphaCut { factor: 1.0, texture: Some(t), cutoff: Some(0.5) });
                }
                Some(_) => other_maps += 1,
                None => {}
            }
        }
        materials.push(material);
        maps.push(MaterialMaps { base_color, normal, alpha, ..MaterialMaps::default() });
    }
    if textures.list.is_empty() {
        maps.clear();
    }
    let notices = vec![
        ("OBJ material librar(ies) not found: their materials drawn grey", missing_libraries),
        ("OBJ material name(s) (usemtl) in no library: drawn grey", undefined),
        ("OBJ texture image(s) (map_Kd) not found: their materials' Kd used", textures.absent[0]),
        ("OBJ texture image(s) (map_Kd) not PNG, JPEG, TGA or BMP: their materials' Kd used", textures.unreadable[0]),
        ("OBJ bump or normal map image(s) not found: their faces shaded flat", textures.absent[1]),
        ("OBJ bump or normal map image(s) not PNG, JPEG, TGA or BMP: their faces shaded flat", textures.unreadable[1]),
        ("OBJ alpha map image(s) (map_d) not found: their faces drawn whole", textures.absent[2]),
        ("OBJ alpha map image(s) (map_d) not PNG, JPEG, TGA or BMP: their faces drawn whole", textures.unreadable[2]),
        (
            "OBJ texture(s) (map_Kd, map_d, bump) not read: the faces have no texture coordinates (vt)",
            textures.without_uvs,
        ),
        ("OBJ texture option(s) (-s, -o, …; all but -bm) not applied", textures.options),
        ("OBJ texture map(s) other than map_Kd, map_d and one bump or normal map not read", other_maps),
        ("partly transparent OBJ material(s) (d, Tr) drawn opaque", dissolving),
        ("specular part(s) (Ks) of diffuse OBJ materials not drawn", specular),
        ("OBJ material colour(s) above 1 clamped to 1", clamped),
    ];
    Ok(ObjMaterials { materials, maps, textures: textures.list, notices })
}

/// The bytes of file `name` in `dir` (at most `limit`), the file and whether it lies inside `dir`;
/// `None` where it does not exist.
fn read_optional(
    dir: &Path,
    name: &str,
    limit: u64,
    options: &LoadOptions,
) -> Result<Option<(Vec<u8>, PathBuf, bool)>, SceneError> {
    let read = resolve_inside(dir, name, options.allow_outside_paths)
        .and_then(|(file, inside)| Ok((read_bounded(&file, limit)?, file, inside)));
    match read {
        Ok(read) => Ok(Some(read)),
        Err(SceneError::Read { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
    }
}

/// The error of material `name`'s map `what`, for an OBJ file's materials.
fn in_material(path: &Path, name: &str, what: &'static str) -> impl Fn(SceneError) -> SceneError {
    let element = format!("material `{}` {what}", visible(&clip(name, 60)));
    move |e| SceneError::InMesh { path: path.to_path_buf(), element: element.clone(), source: Box::new(e) }
}

/// Where a map is read: texture `texture` at the faces' `vt` coordinates.
fn texture_ref(texture: u32) -> TextureRef {
    TextureRef { texture, tex_coord: 0, transform: Affine2::IDENTITY }
}

/// How a map's image is read: as colour, as a bump map (heights scaled by `-bm`, unless it is
/// or looks like a normal map), or as alpha ([`alpha_texels`]).
#[derive(Clone, Copy)]
enum Kind {
    Colour,
    Bump { normal: bool, scale: f32 },
    Alpha,
}

/// A texture read: its index in [`Textures::list`] and whether it is a normal map.
type Read = (u32, bool);

/// An alpha map's texels as white of its alpha: the image's own alpha where any texel has some,
/// else its grey level (the mean of its channels), as Blender reads `map_d`.
fn alpha_texels(texels: &[[u8; 4]]) -> Arc<[[u8; 4]]> {
    let has_alpha = texels.iter().any(|t| t[3] < u8::MAX);
    let alpha =
        |t: &[u8; 4]| if has_alpha { t[3] } else { ((u16::from(t[0]) + u16::from(t[1]) + u16::from(t[2])) / 3) as u8 };
    texels.iter().map(|t| [u8::MAX, u8::MAX, u8::MAX, alpha(t)]).collect()
}

/// The maps' textures read so far, each file and kind decoded once, and the counts for the notices
/// (`[colour, bump, alpha]`).
#[derive(Default)]
struct Textures {
    list: Vec<Texture>,
    /// Index in `list` of each file read as a kind, and whether it is a normal map (`None`: it
    /// could not be read).
    by_file: HashMap<(PathBuf, [u32; 2]), Option<Read>>,
    absent: [usize; 3],
    unreadable: [usize; 3],
    without_uvs: usize,
    options: usize,
}

impl Textures {
    /// [`Textures::read`] for a map statement `(file, with_options)`: options other than `-bm`
    /// are counted, not applied; `error` names the material and the map.
    fn read_map(
        &mut self,
        folder: &Path,
        (file, with_options): (&str, bool),
        kind: Kind,
        (stats, options): (&ObjStats, &LoadOptions),
        error: impl Fn(SceneError) -> SceneError,
    ) -> Result<Option<Read>, SceneError> {
        self.options += usize::from(with_options);
        self.read(folder, file, kind, stats, options).map_err(error)
    }

    /// The texture of file `name` (as an MTL file in `folder` writes it) read as `kind`: its index
    /// in `list` and whether it is a normal map, or `None` where it is missing or not a PNG, JPEG,
    /// TGA or BMP image, or the faces have no texture coordinates (counted).
    fn read(
        &mut self,
        folder: &Path,
        name: &str,
        kind: Kind,
        stats: &ObjStats,
        options: &LoadOptions,
    ) -> Result<Option<Read>, SceneError> {
        if stats.triangle_uvs.is_empty() {
            self.without_uvs += 1;
            return Ok(None);
        }
        let name = name.replace('\\', "/");
        let (slot, key) = match kind {
            Kind::Colour => (0, [0, 0]),
            Kind::Bump { normal, scale } => (1, [1 + u32::from(normal), scale.to_bits()]),
            Kind::Alpha => (2, [3, 0]),
        };
        let file = (folder.join(&name), key);
        if let Some(&known) = self.by_file.get(&file) {
            return Ok(known);
        }
        let index = match read_optional(folder, &name, MAX_MESH_BYTES, options)? {
            None => {
                self.absent[slot] += 1;
                None
            }
            Some((bytes, _, _)) => match decode_image(bytes, &name, &MTL_IMAGES) {
                Ok((width, height, texels)) => {
                    let (texels, normal) = match kind {
                        Kind::Colour => (texels, false),
                        Kind::Alpha => (alpha_texels(&texels), false),
                        Kind::Bump { normal, .. } if normal || is_normal_map(&texels) => (texels, true),
                        Kind::Bump { scale, .. } => (height_to_normals(width, height, &texels, scale), false),
                    };
                    self.list.push(Texture { width, height, texels, wrap: [Wrap::Repeat; 2], filter: Filter::Linear });
                    Some((self.list.len() as u32 - 1, normal))
                }
                Err(_) => {
                    self.unreadable[slot] += 1;
                    None
                }
            },
        };
        self.by_file.insert(file, index);
        Ok(index)
    }
}
