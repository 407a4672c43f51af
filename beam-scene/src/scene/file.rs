//! Loading scene files (TOML, format in [`super::format`]), glTF 2.0 files ([`super::gltf`]) and
//! bare OBJ files.

use super::check::{self, finite};
use super::defaults::{default_camera, default_light, valid_bounds};
use super::environment::Environment;
use super::format::{self, Scale, SceneFile};
use super::interior;
use super::light::Light;
use super::load_options::LoadOptions;
use super::material::Material;
use super::model::Scene;
use super::names::{BUILTIN, GENERATED};
use super::obj_materials::{ObjMaterials, obj_materials};
use super::smesh_file;
use super::smesh_plan::SMeshPlan;
use super::surface::Surfaces;
use crate::error::SceneError;
use crate::mesh::{Mesh, load_obj_with};
use crate::read::{MAX_SCENE_BYTES, has_extension, read_bounded, resolve_inside};
use beam_math::Triangle;
use beam_math::glam::{EulerRot, Mat3, Vec3};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// Load a scene by built-in name, `.toml` scene file, `.gltf`/`.glb` file or bare `.obj` file,
/// with mesh and buffer paths kept inside the scene file's folder.
pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
    load_with(name_or_path, &LoadOptions::default())
}

/// [`load`] with `options`.
pub fn load_with(name_or_path: &str, options: &LoadOptions) -> Result<Scene, SceneError> {
    if BUILTIN.contains(&name_or_path) || GENERATED.contains(&name_or_path) {
        return super::builtin::builtin(name_or_path);
    }
    load_file_with(Path::new(name_or_path), options)
}

/// Load a `.toml` scene file, a `.gltf` or `.glb` file or a bare `.obj` file (extensions in any
/// case), with mesh and buffer paths kept inside the scene file's folder. Errors name the file and
/// the line (TOML syntax, OBJ lines) or the element (`meshes[2].material`, `mesh 2 primitive 0`).
pub fn load_file(path: &Path) -> Result<Scene, SceneError> {
    load_file_with(path, &LoadOptions::default())
}

/// [`load_file`] with `options`.
pub fn load_file_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    if has_extension(path, "obj") {
        load_bare_obj(path, options)
    } else if has_extension(path, "toml") {
        load_toml(path, options)
    } else if has_extension(path, "gltf") || has_extension(path, "glb") {
        super::gltf::load_gltf(path, options)
    } else {
        Err(SceneError::UnknownFileType { path: path.to_path_buf() })
    }
}

/// The scene file's text, read once (bounded), checked for UTF-8 and nesting depth, and parsed.
fn parse_toml(path: &Path) -> Result<SceneFile, SceneError> {
    let data = read_bounded(path, MAX_SCENE_BYTES)?;
    let text = String::from_utf8(data).map_err(|e| {
        let line = e.as_bytes()[..e.utf8_error().valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        SceneError::Toml { path: path.to_path_buf(), line: Some(line), column: None, message: "not UTF-8 text".into() }
    })?;
    check::nesting(path, &text)?;
    toml::from_str(&text).map_err(|e| check::toml_error(path, &text, &e))
}

fn load_toml(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let file = parse_toml(path)?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut materials = Vec::new();
    let mut index = BTreeMap::new();
    for (name, m) in &file.materials {
        let element = format!("materials.{}", check::name(name));
        let m = format::material(path, &element, m)?;
        index.insert(name.clone(), materials.len() as u32);
        materials.push(m);
    }
    let mut triangles: Vec<(Triangle, u32)> = Vec::new();
    // Each mesh file is read once, however many meshes name it.
    let mut meshes: HashMap<PathBuf, (Mesh, Vec<[Vec3; 3]>)> = HashMap::new();
    // Per triangle, its corners' shading normals (`vn`, placed with the mesh), once any mesh has them.
    let mut normals: Vec<[Vec3; 3]> = Vec::new();
    let (mut skipped, mut own_materials) = (0, 0);
    // S-mesh sources by range of the scene's (valid) triangles.
    let (mut valid, mut parts) = (0u32, Vec::new());
    for (i, m) in file.meshes.iter().enumerate() {
        let element = format!("meshes[{i}]");
        let &mat = index.get(&m.material).ok_or_else(|| SceneError::Invalid {
            path: path.to_path_buf(),
            element: format!("{element}.material"),
            message: format!("no material named `{}`", check::name(&m.material)),
        })?;
        let scale = match m.scale {
            None => Vec3::ONE,
            Some(Scale::Uniform(s)) => Vec3::splat(s),
            Some(Scale::Axes(a)) => Vec3::from_array(a),
        };
        let r = m.rotate.map_or(Vec3::ZERO, Vec3::from_array);
        let t = m.translate.map_or(Vec3::ZERO, Vec3::from_array);
        finite(path, &format!("{element} transform"), &[scale.x, scale.y, scale.z, r.x, r.y, r.z, t.x, t.y, t.z])?;
        let rot = Mat3::from_euler(EulerRot::XYZ, r.x.to_radians(), r.y.to_radians(), r.z.to_radians());
        let in_scene =
            |e| SceneError::InMesh { path: path.to_path_buf(), element: element.clone(), source: Box::new(e) };
        let (mesh_path, inside) = resolve_inside(dir, &m.file, options.allow_outside_paths).map_err(in_scene)?;
        if !meshes.contains_key(&mesh_path) {
            let (mesh, stats) = load_obj_with(&mesh_path, inside).map_err(in_scene)?;
            skipped += stats.skipped_elements;
            own_materials += usize::from(!stats.materials.is_empty());
            meshes.insert(mesh_path.clone(), (mesh, stats.triangle_normals));
        }
        let first = triangles.len();
        let (mesh, mesh_normals) = &meshes[&mesh_path];
        if !mesh_normals.is_empty() {
            // Normals go by the inverse transpose of `rot · scale`: `rot · (n / scale)`.
            normals.resize(triangles.len(), [Vec3::ZERO; 3]);
            normals.extend(mesh_normals.iter().map(|c| c.map(|n| (rot * (n / scale)).normalize_or_zero())));
        }
        for tri in mesh.triangles() {
            triangles.push((Triangle { v: tri.v.map(|v| rot * (v * scale) + t) }, mat));
        }
        let fine: Vec<Triangle> = triangles[first..].iter().map(|(t, _)| *t).collect();
        let start = valid;
        valid += fine.iter().filter(|t| t.is_valid()).count() as u32;
        let material = (&materials[mat as usize], m.material.as_str());
        let place = |v: Vec3| rot * (v * scale) + t;
        let allow = options.allow_outside_paths;
        if let Some(source) = smesh_file::mesh_source(path, dir, allow, &element, m, material, place, &fine)? {
            parts.push((start..valid, source));
        }
    }
    let rest = smesh_file::rest(path, file.smesh.as_ref())?;
    let environment = match &file.environment {
        Some(e) => super::environment_file::environment(path, dir, options.allow_outside_paths, e)?,
        None => Environment::Black,
    };
    let mut lights = Vec::new();
    for (i, l) in file.lights.iter().enumerate() {
        let element = format!("lights[{i}]");
        let light = format::light(path, &element, l)?;
        lights.push(light);
    }
    valid_bounds(path, &triangles)?;
    let framed = file.camera.is_none();
    let (camera, camera_path) = match file.camera {
        Some(c) => format::camera(path, &c)?,
        None => (default_camera(&triangles), None),
    };
    let default_lit = lights.is_empty();
    if default_lit {
        lights.push(default_light(&triangles, &camera));
    }
    if !normals.is_empty() {
        normals.resize(triangles.len(), [Vec3::ZERO; 3]);
    }
    let surfaces = Surfaces { normals, ..Surfaces::default() };
    let mut scene = Scene::with_surfaces(path.display().to_string(), triangles, materials, lights, camera, surfaces);
    if framed {
        interior::look_inside(&mut scene, default_lit);
    }
    scene.stats.skipped_elements = skipped;
    scene.notice("OBJ line and point element(s) skipped: they have no area to render", skipped);
    scene.notice("OBJ file(s) with their own materials (usemtl) drawn with their [[meshes]] material", own_materials);
    scene.camera_path = camera_path;
    scene.smesh = SMeshPlan { parts, rest };
    scene.environment = environment;
    Ok(scene)
}

/// A bare OBJ file with the materials of its MTL libraries ([`obj_materials`]) and its vertex
/// normals (`vn`) as shading normals, its emissive triangles as triangle lights, and the framing
/// camera; without an emitter, the default light.
fn load_bare_obj(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let (mesh, stats) = load_obj_with(path, true)?;
    let ObjMaterials { materials, maps, textures, notices } = obj_materials(path, &stats, options)?;
    let triangles: Vec<(Triangle, u32)> = mesh.triangles().into_iter().zip(stats.triangle_materials).collect();
    let uv = if maps.is_empty() { Vec::new() } else { stats.triangle_uvs };
    let surfaces =
        Surfaces { uv: [uv, Vec::new()], textures, maps, normals: stats.triangle_normals, ..Surfaces::default() };
    valid_bounds(path, &triangles)?;
    let camera = default_camera(&triangles);
    let mut lights: Vec<Light> = triangles
        .iter()
        .filter(|(t, _)| t.is_valid())
        .filter_map(|&(t, m)| match materials[m as usize] {
            Material::Emissive { radiance } => Some(Light::Triangle { v: t.v, radiance }),
            _ => None,
        })
        .collect();
    let default_lit = lights.is_empty();
    if default_lit {
        lights.push(default_light(&triangles, &camera));
    }
    let mut scene = Scene::with_surfaces(path.display().to_string(), triangles, materials, lights, camera, surfaces);
    interior::look_inside(&mut scene, default_lit);
    scene.stats.skipped_elements = stats.skipped_elements;
    scene.notice("OBJ line and point element(s) skipped: they have no area to render", stats.skipped_elements);
    for (what, count) in notices {
        scene.notice(what, count);
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SMeshSource, Simplify};

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn loads_a_scene_file_with_relative_meshes() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("m")).unwrap();
        write(&dir.path().join("m"), "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\nf 1 1 2\n");
        let scene = write(
            dir.path(),
            "s.toml",
            "[materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\n[[meshes]]\nfile = \"m/tri.obj\"\nmaterial = \"w\"\ntranslate = [1, 0, 0]\n\n[[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = [1, 1, 1]\n",
        );
        let s = load_file(&scene).unwrap();
        assert_eq!(s.stats.triangles, 1);
        assert_eq!(s.stats.degenerate, 1);
        assert_eq!(s.triangles[0].v[1], Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(s.lights.len(), 1);
    }

    /// A Cornell-box corner as a bare OBJ with its MTL library: each face takes its material's
    /// colour, the emissive quad becomes the only light, a polished box is glossy, and what is not
    /// read is counted.
    #[test]
    fn a_bare_obj_takes_its_mtl_materials_and_emitters() {
        let dir = tempfile::tempdir().unwrap();
        write(
            dir.path(),
            "box.mtl",
            "newmtl red\nKd 0.63 0.065 0.05\nKs 0.1 0.1 0.1\nnewmtl light\nKd 0.78 0.78 0.78\nKe 17 12 4\n\
             newmtl shiny\nKd 0 0 0\nKs 0.7 0.7 0.7\nNs 200\nmap_Ks s.png\nd 0.5\n",
        );
        let obj = "mtllib box.mtl missing.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n\
                   f 1 2 3\nusemtl red\nf 1 3 4\nusemtl light\nf 1 2 3 4\nusemtl shiny\nf 1 2 5\n\
                   usemtl nowhere\nf 1 4 5\nusemtl red\nf 2 3 5\n";
        let path = write(dir.path(), "box.obj", obj);
        let s = load_file(&path).unwrap();
        let materials: Vec<Material> = (0..s.triangles.len() as u32).map(|i| s.material(i)).collect();
        let grey = Material::Diffuse { albedo: Vec3::splat(0.7) };
        let red = Material::Diffuse { albedo: Vec3::new(0.63, 0.065, 0.05) };
        let light = Material::Emissive { radiance: Vec3::new(17.0, 12.0, 4.0) };
        let shiny = Material::Glossy { albedo: Vec3::splat(0.7), variance: 0.25 / 200.0 };
        assert_eq!(materials, [grey, red, light, light, shiny, grey, red]);
        // The emissive quad's two triangles, joined into one quad light; no default light.
        assert_eq!(s.lights.len(), 1, "{:?}", s.lights);
        assert!(matches!(s.lights[0], Light::Quad { radiance, .. } if radiance == Vec3::new(17.0, 12.0, 4.0)));
        let noticed = |what: &str| s.notices.iter().find(|n| n.what.contains(what)).map(|n| n.count);
        assert_eq!(noticed("librar(ies) not found"), Some(1));
        assert_eq!(noticed("in no library"), Some(1));
        assert_eq!(noticed("other than map_Kd"), Some(1));
        assert_eq!(noticed("partly transparent"), Some(1));
        assert_eq!(noticed("specular part(s)"), Some(1));
        // Without a library the faces are grey and the default light shows them.
        let bare = write(dir.path(), "bare.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
        let s = load_file(&bare).unwrap();
        assert_eq!(s.material(0), grey);
        assert_eq!(s.lights.len(), 1);
    }

    /// A quad with a 2 × 2 texture (red, green / blue, white) under `map_Kd`, its path written with
    /// a backslash: each quarter of the quad reads its texel (from sRGB), `v` up as OBJ has it;
    /// the same image as a TGA file likewise; a missing and an unreadable image leave `Kd` and are
    /// counted; `vt nan` loads.
    #[test]
    fn a_bare_obj_reads_its_map_kd_texture() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("tex")).unwrap();
        let texels = [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255, 255, 255, 255]];
        let img = image::RgbaImage::from_fn(2, 2, |x, y| image::Rgba(texels[(y * 2 + x) as usize]));
        img.save(dir.path().join("tex/t.png")).unwrap();
        img.save_with_format(dir.path().join("tex/t.tga"), image::ImageFormat::Tga).unwrap();
        write(&dir.path().join("tex"), "b.tga", "not an image");
        write(
            dir.path(),
            "q.mtl",
            "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd tex\\t.png\nnewmtl gone\nKd 0.2 0.2 0.2\nmap_Kd none.png\n\
             newmtl tga\nKd 0.3 0.3 0.3\nmap_Kd tex/t.tga\nnewmtl bad\nKd 0.4 0.4 0.4\nmap_Kd tex/b.tga\n",
        );
        let obj = "mtllib q.mtl\nv 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                   vt nan -inf\nusemtl tex\nf 1/1 2/2 3/3 4/4\nusemtl gone\nf 1/1 2/2 3/3\nusemtl tga\n\
                   f 1/1 3/3 4/4\nusemtl tex\nf 1/5 2/5 3/5\nusemtl bad\nf 1/1 2/2 3/3\n";
        let s = load_file(&write(dir.path(), "q.obj", obj)).unwrap();
        // The image's top row (red, green) is at v = 1, the quad's top (y = 2).
        for (p, colour) in [
            (Vec3::new(0.5, 1.5, 0.0), Vec3::X),
            (Vec3::new(1.5, 1.5, 0.0), Vec3::Y),
            (Vec3::new(0.5, 0.5, 0.0), Vec3::Z),
            (Vec3::new(1.5, 0.5, 0.0), Vec3::ONE),
        ] {
            let prim = if p.x > p.y { 0 } else { 1 };
            let a = s.albedo_at(prim, p);
            // Bilinear between texel centres: the quarter's centre reads its own texel whole.
            assert!((a - colour).abs().max_element() < 1e-3, "{p}: {a}, not {colour}");
        }
        assert_eq!(s.albedo_at(2, Vec3::new(1.5, 0.5, 0.0)), Vec3::splat(0.2));
        // The same image as a TGA file.
        let a = s.albedo_at(3, Vec3::new(0.5, 1.5, 0.0));
        assert!((a - Vec3::X).abs().max_element() < 1e-3, "TGA: {a}");
        // Coordinates that are not finite (written for degenerate faces) read the image still.
        let a = s.albedo_at(4, Vec3::new(1.5, 0.5, 0.0));
        assert!(a.is_finite() && a.max_element() <= 1.0 && a.min_element() >= 0.0, "{a}");
        assert_eq!(s.albedo_at(5, Vec3::new(1.5, 0.5, 0.0)), Vec3::splat(0.4));
        let noticed = |what: &str| s.notices.iter().find(|n| n.what.contains(what)).map(|n| n.count);
        assert_eq!(noticed("not found: their materials' Kd"), Some(1));
        assert_eq!(noticed("not PNG, JPEG, TGA or BMP"), Some(1));
    }

    /// A bump map bends a bare OBJ's shading normals: heights rising along `u` (`map_Bump -bm 4`)
    /// tilt them against it; a `norm` normal map and a normal map written as `map_Bump` (as
    /// Blender writes them) tilt them as their texels say; a missing map leaves the face flat and
    /// is counted.
    #[test]
    fn a_bare_obj_reads_its_bump_and_normal_maps() {
        let dir = tempfile::tempdir().unwrap();
        let ramp = image::RgbaImage::from_fn(16, 16, |x, _| {
            let c = (x * 16) as u8;
            image::Rgba([c, c, c, 255])
        });
        ramp.save(dir.path().join("h.png")).unwrap();
        image::RgbaImage::from_pixel(4, 4, image::Rgba([150, 128, 255, 255])).save(dir.path().join("n.png")).unwrap();
        write(
            dir.path(),
            "b.mtl",
            "newmtl heights\nKd 0.5 0.5 0.5\nmap_Bump -bm 4 h.png\nnewmtl norm\nKd 0.5 0.5 0.5\nnorm n.png\n\
             newmtl blender\nKd 0.5 0.5 0.5\nmap_Bump -bm 1.0 n.png\nnewmtl gone\nKd 0.5 0.5 0.5\nbump none.png\n",
        );
        let obj = "mtllib b.mtl\nv 0 0 0\nv 2 0 0\nv 2 2 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl heights\nf 1/1 2/2 3/3\n\
                   usemtl norm\nf 1/1 2/2 3/3\nusemtl blender\nf 1/1 2/2 3/3\nusemtl gone\nf 1/1 2/2 3/3\n";
        let s = load_file(&write(dir.path(), "b.obj", obj)).unwrap();
        let at = |prim: u32| s.mapped_normal(prim, Vec3::new(1.5, 0.5, 0.0), Vec3::Z);
        // u along x: a slope of 4 / 16 a texel tilts the normal to (−0.25, 0, 1), normalized.
        let expect = Vec3::new(-0.25, 0.0, 1.0).normalize();
        assert!((at(0) - expect).length() < 0.02, "heights: {}", at(0));
        let tilted = Vec3::new(150.0 / 255.0 * 2.0 - 1.0, 128.0 / 255.0 * 2.0 - 1.0, 1.0).normalize();
        assert!((at(1) - tilted).length() < 0.01, "norm: {}", at(1));
        assert!((at(2) - tilted).length() < 0.01, "a normal map as map_Bump: {}", at(2));
        assert_eq!(at(3), Vec3::Z, "a missing map: flat");
        let noticed = |what: &str| s.notices.iter().find(|n| n.what.contains(what)).map(|n| n.count);
        assert_eq!(noticed("bump or normal map image(s) not found"), Some(1));
    }

    /// `vn` normals shade a bare OBJ's faces smoothly: a quad (two triangles) whose corners lean
    /// out along x gives each point the interpolation of its triangle's corners; a face without
    /// normals keeps its own; an index past the last normal is an error naming the line.
    #[test]
    fn a_bare_obj_is_shaded_by_its_vertex_normals() {
        let dir = tempfile::tempdir().unwrap();
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn -1 0 1\nvn 1 0 1\nvn -nan nan 0\n\
                   f 1//1 2//2 3//2 4//1\nf 1 3 4\nf 1//3 2//2 3//2\n";
        let s = load_file(&write(dir.path(), "n.obj", obj)).unwrap();
        let at = |prim: u32, x: f32| s.mapped_normal(prim, Vec3::new(x, 0.5, 0.0), Vec3::Z);
        assert!((at(0, 0.75) - Vec3::new(0.5, 0.0, 1.0).normalize()).length() < 1e-5, "{}", at(0, 0.75));
        assert!((at(1, 0.5) - Vec3::Z).length() < 1e-5, "{}", at(1, 0.5));
        assert!((at(2, 0.25) - Vec3::Z).length() < 1e-6, "no vn: the face's own normal");
        assert!((at(3, 0.75) - Vec3::Z).length() < 1e-6, "a `nan` normal: the face's own");
        let bad = write(dir.path(), "b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n");
        let e = load_file(&bad).err().unwrap().to_string();
        assert!(e.contains("b.obj:5: normal 2 is past the last (1)"), "{e}");
    }

    /// A scene file's mesh keeps its `vn` normals, placed with it: a scale of 2 along x halves
    /// their x, a turn of 90° about z takes x to y.
    #[test]
    fn a_scene_mesh_keeps_its_vertex_normals_through_its_transform() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 1\nf 1//1 2//1 3//1\n");
        write(dir.path(), "flat.obj", "v 0 0 5\nv 1 0 5\nv 0 1 5\nf 1 2 3\n");
        let body = "[materials.w]\ntype=\"diffuse\"\nalbedo=[1,1,1]\n[[meshes]]\nfile=\"flat.obj\"\nmaterial=\"w\"\n\
                    [[meshes]]\nfile=\"n.obj\"\nmaterial=\"w\"\nscale=[2,1,1]\nrotate=[0,0,90]\n";
        let s = load_file(&write(dir.path(), "s.toml", body)).unwrap();
        let n = s.mapped_normal(1, s.triangles[1].v[0], Vec3::Z);
        let want = Vec3::new(0.0, 0.5, 1.0).normalize();
        assert!((n - want).length() < 1e-5, "{n} against {want}");
        assert_eq!(s.mapped_normal(0, Vec3::new(0.2, 0.2, 5.0), Vec3::Z), Vec3::Z, "the mesh without vn");
    }

    #[test]
    fn mtl_errors_name_the_obj_line_and_the_library_line() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "bad.mtl", "newmtl a\nKd 1 oops 1\n");
        let obj = write(dir.path(), "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib bad.mtl\nusemtl a\nf 1 2 3\n");
        let e = load_file(&obj).err().unwrap().to_string();
        assert!(e.contains("a.obj: mtllib on line 4: ") && e.contains("bad.mtl:2: "), "{e}");
        let outside = write(dir.path(), "b.obj", "mtllib ../x.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let e = load_file(&outside).err().unwrap().to_string();
        assert!(e.contains("b.obj: mtllib on line 1: ") && e.contains("--allow-outside-paths"), "{e}");
    }

    #[test]
    fn errors_name_the_file_and_line_or_element() {
        let dir = tempfile::tempdir().unwrap();
        let bad_syntax = write(dir.path(), "a.toml", "[camera]\nposition = [0, 0\n");
        let e = load_file(&bad_syntax).err().unwrap().to_string();
        assert!(e.contains("a.toml:2:"), "{e}");
        let bad_material = write(dir.path(), "b.toml", "[[meshes]]\nfile = \"x.obj\"\nmaterial = \"nope\"\n");
        let e = load_file(&bad_material).err().unwrap().to_string();
        assert!(e.contains("b.toml") && e.contains("meshes[0].material"), "{e}");
        let zero_light = write(
            dir.path(),
            "c.toml",
            "[materials.w]\ntype=\"diffuse\"\nalbedo=[1,1,1]\n[[meshes]]\nfile=\"t.obj\"\nmaterial=\"w\"\n[[lights]]\ntype=\"quad\"\ncorner=[0,0,0]\nedge_u=[1,0,0]\nedge_v=[2,0,0]\nradiance=[1,1,1]\n",
        );
        write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let e = load_file(&zero_light).err().unwrap().to_string();
        assert!(e.contains("lights[0]") && e.contains("zero area"), "{e}");
        let bad_obj = write(dir.path(), "d.obj", "v 0 0 0\nv 1 x 0\nf 1 2 3\n");
        let e = load_file(&bad_obj).err().unwrap().to_string();
        assert!(e.contains("d.obj:2"), "{e}");
    }

    #[test]
    fn camera_keys_make_an_animated_camera() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let body = "[materials.w]\ntype=\"diffuse\"\nalbedo=[1,1,1]\n[[meshes]]\nfile=\"t.obj\"\nmaterial=\"w\"\n";
        let key =
            |f: u32, x: f32| format!("[[camera.keys]]\nframe = {f}\nposition = [{x}, 0, 5]\ntarget = [0, 0, 0]\n");
        let p = write(dir.path(), "a.toml", &format!("{body}[camera]\nfov = 30\n{}{}", key(0, 0.0), key(4, 2.0)));
        let s = load_file(&p).unwrap();
        assert_eq!(s.camera.position, Vec3::new(0.0, 0.0, 5.0));
        assert_eq!(s.camera_at(2).unwrap().position, Vec3::new(1.0, 0.0, 5.0));
        assert_eq!(s.camera_at(2).unwrap().fov_y, 30.0);
        assert!(s.camera_at(5).is_none());
        let still = write(dir.path(), "b.toml", &format!("{body}[camera]\nposition = [0, 0, 5]\ntarget = [0, 0, 0]\n"));
        let s = load_file(&still).unwrap();
        assert!(s.camera_path.is_none() && s.camera_at(0) == Some(s.camera) && s.camera_at(1).is_none());
        let both = write(
            dir.path(),
            "c.toml",
            &format!("{body}[camera]\nposition = [0, 0, 5]\ntarget = [0, 0, 0]\n{}", key(0, 0.0)),
        );
        assert!(load_file(&both).err().unwrap().to_string().contains("not both"));
        let back = write(dir.path(), "d.toml", &format!("{body}{}{}", key(3, 0.0), key(3, 1.0)));
        let e = load_file(&back).err().unwrap().to_string();
        assert!(e.contains("camera.keys[1].frame 3") && e.contains("increase"), "{e}");
        let blind = write(
            dir.path(),
            "e.toml",
            &format!("{body}{}[[camera.keys]]\nframe = 1\nposition = [0, 0, 0]\ntarget = [0, 0, 0]\n", key(0, 0.0)),
        );
        assert!(load_file(&blind).err().unwrap().to_string().contains("camera.keys[1]"));
        let none = write(dir.path(), "f.toml", &format!("{body}[camera]\nfov = 30\n"));
        assert!(load_file(&none).err().unwrap().to_string().contains("needs position and target"));
    }

    #[test]
    fn smesh_keys_give_coarse_meshes_or_clear_errors() {
        let dir = tempfile::tempdir().unwrap();
        // A unit tetrahedron-ish fan and a coarse triangle over it.
        write(
            dir.path(),
            "fine.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0.1\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n",
        );
        write(dir.path(), "coarse.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
        write(dir.path(), "far.obj", "v 10 0 0\nv 11 0 0\nv 11 1 0\nf 1 2 3\n");
        write(dir.path(), "bad.obj", "v 0 0 0\nv 1 0\nf 1 2 3\n");
        let materials = "[materials.m]\ntype = \"mirror\"\n[materials.w]\ntype = \"diffuse\"\nalbedo = [1, 1, 1]\n";
        let scene = |name: &str, mesh: &str, extra: &str| {
            let text = format!(
                "{materials}[[meshes]]\nfile = \"fine.obj\"\nmaterial = \"m\"\ntranslate = [2, 0, 0]\n{mesh}\n{extra}"
            );
            load_file(&write(dir.path(), name, &text))
        };
        let s = scene("a.toml", "smesh = \"coarse.obj\"", "").unwrap();
        match &s.smesh.parts[..] {
            [(r, SMeshSource::Given(m))] => {
                assert_eq!(*r, 0..4);
                assert_eq!(m.indices.len(), 2);
                assert_eq!(m.positions[1], Vec3::new(3.0, 0.0, 0.0), "moved with its mesh");
            }
            other => panic!("{other:?}"),
        }
        let s = scene("b.toml", "smesh_target = 8", "[smesh]\nerror = 0.02\n").unwrap();
        assert!(matches!(s.smesh.parts[..], [(_, SMeshSource::Simplified(Simplify::Faces(8)))]));
        assert_eq!(s.smesh.rest, Some(Simplify::Error(0.02)));
        let err = |name: &str, mesh: &str, extra: &str| scene(name, mesh, extra).err().unwrap().to_string();
        let e = err("c.toml", "smesh = \"far.obj\"", "");
        assert!(e.contains("c.toml") && e.contains("meshes[0].smesh") && e.contains("does not lie over"), "{e}");
        let e = err("d.toml", "smesh = \"bad.obj\"", "");
        assert!(e.contains("meshes[0].smesh") && e.contains("bad.obj:2"), "{e}");
        let e = err("e.toml", "smesh = \"none.obj\"", "");
        assert!(e.contains("meshes[0].smesh") && e.contains("none.obj"), "{e}");
        let e = err("f.toml", "smesh_target = 2", "");
        assert!(e.contains("meshes[0].smesh_target must be a face count from 4"), "{e}");
        let e = err("g.toml", "smesh_target = 8\nsmesh_error = 0.1", "");
        assert!(e.contains("not both"), "{e}");
        let e = err("h.toml", "smesh = \"coarse.obj\"\nsmesh_error = 0.1", "");
        assert!(e.contains("not both"), "{e}");
        let e = err("i.toml", "", "[smesh]\nerror = 0\n");
        assert!(e.contains("smesh.error must be an error above 0"), "{e}");
        let diffuse = format!("{materials}[[meshes]]\nfile = \"fine.obj\"\nmaterial = \"w\"\nsmesh_target = 8\n");
        let e = load_file(&write(dir.path(), "j.toml", &diffuse)).err().unwrap().to_string();
        assert!(e.contains("meshes[0].smesh_target") && e.contains("not material `w`"), "{e}");
        let e = err("k.toml", "smesh = 3", "");
        assert!(e.contains("k.toml:"), "{e}");
    }

    #[test]
    fn bare_obj_gets_a_camera_and_light() {
        let dir = tempfile::tempdir().unwrap();
        let p = write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let s = load(p.to_str().unwrap()).unwrap();
        assert_eq!(s.lights.len(), 1);
        assert!(s.camera.position.z > 0.5);
    }

    /// A room (a unit box without its +z wall, its faces turned in) as a bare OBJ and in a TOML
    /// scene without a camera or light is seen from its open side and lit from under its ceiling;
    /// a TOML camera is kept.
    #[test]
    fn a_room_is_framed_from_inside() {
        let dir = tempfile::tempdir().unwrap();
        let room = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                    f 1 2 3 4\nf 1 4 8 5\nf 2 6 7 3\nf 1 5 6 2\nf 4 3 7 8\n";
        let obj = write(dir.path(), "room.obj", room);
        let mesh = "[materials.w]\ntype = \"diffuse\"\nalbedo = [0.7, 0.7, 0.7]\n[[meshes]]\nfile = \"room.obj\"\nmaterial = \"w\"\n";
        let toml = write(dir.path(), "room.toml", mesh);
        let kept =
            write(dir.path(), "kept.toml", &format!("[camera]\nposition = [3, 3, 3]\ntarget = [0, 0, 0]\n{mesh}"));
        for path in [obj, toml] {
            let s = load_file(&path).unwrap();
            assert!(s.camera.position.z > 1.0 && s.camera.target == Vec3::splat(0.5), "{:?}", s.camera);
            let [Light::Quad { corner, .. }] = s.lights[..] else { panic!("{:?}", s.lights) };
            assert!((corner.y - 0.99).abs() < 1e-5, "under the ceiling: {corner}");
        }
        assert_eq!(load_file(&kept).unwrap().camera.position, Vec3::splat(3.0));
    }
}
