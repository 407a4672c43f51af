//! Scene files (TOML) and bare OBJ files.
//!
//! ```toml
//! [camera]                      # optional for a scene made of one mesh
//! position = [0, 1, 4]
//! target = [0, 1, 0]
//! up = [0, 1, 0]                # default [0, 1, 0]
//! fov = 45                      # vertical, degrees; default 45
//! width = 512                   # default 512
//! height = 512                  # default 512
//!
//! [materials.white]             # type: diffuse | mirror | glass | glossy | emissive
//! type = "diffuse"
//! albedo = [0.7, 0.7, 0.7]
//!
//! [[meshes]]
//! file = "bunny.obj"            # relative to this file's folder
//! material = "white"
//! translate = [0, 0, 0]         # optional transform: scale, then rotate (degrees about x, y, z), then translate
//! rotate = [0, 90, 0]
//! scale = 1.0                   # a number or [x, y, z]
//!
//! [[lights]]                    # type: point | quad | triangle
//! type = "quad"
//! corner = [-0.5, 2, -0.5]
//! edge_u = [1, 0, 0]
//! edge_v = [0, 0, 1]
//! radiance = [10, 10, 10]       # intensity for a point light
//! ```

use super::{Bump, Camera, Light, Material, Scene};
use crate::mesh::load_obj;
use beam_math::Triangle;
use beam_math::glam::{EulerRot, Mat3, Vec3};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    camera: Option<CameraFile>,
    #[serde(default)]
    materials: BTreeMap<String, MaterialFile>,
    #[serde(default)]
    meshes: Vec<MeshFile>,
    #[serde(default)]
    lights: Vec<LightFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    position: [f32; 3],
    target: [f32; 3],
    up: Option<[f32; 3]>,
    fov: Option<f32>,
    width: Option<u32>,
    height: Option<u32>,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum MaterialFile {
    Diffuse {
        albedo: [f32; 3],
    },
    Mirror {
        tint: Option<[f32; 3]>,
        bump: Option<f32>,
        bump_wavelength: Option<f32>,
    },
    Glass {
        ior: f32,
    },
    Glossy {
        albedo: [f32; 3],
        variance: f32,
    },
    #[serde(rename = "thin-glass")]
    ThinGlass {
        tint: [f32; 3],
        sigma: Option<f32>,
    },
    Emissive {
        radiance: [f32; 3],
    },
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Scale {
    Uniform(f32),
    Axes([f32; 3]),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshFile {
    file: String,
    material: String,
    translate: Option<[f32; 3]>,
    rotate: Option<[f32; 3]>,
    scale: Option<Scale>,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum LightFile {
    Point { position: [f32; 3], intensity: [f32; 3] },
    Quad { corner: [f32; 3], edge_u: [f32; 3], edge_v: [f32; 3], radiance: [f32; 3] },
    Triangle { vertices: [[f32; 3]; 3], radiance: [f32; 3] },
}

/// Load a scene by built-in name, `.toml` scene file or bare `.obj` file.
pub fn load(name_or_path: &str) -> Result<Scene, String> {
    if super::BUILTIN.contains(&name_or_path) {
        return super::builtin(name_or_path);
    }
    load_file(Path::new(name_or_path))
}

/// Load a `.toml` scene file or a bare `.obj` file. Errors name the file and the line (TOML syntax,
/// OBJ lines) or the element (`meshes[2].material`).
pub fn load_file(path: &Path) -> Result<Scene, String> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("obj") => load_bare_obj(path),
        Some("toml") => load_toml(path),
        _ => Err(format!(
            "{}: expected a built-in scene name ({}), a .toml scene or an .obj mesh",
            path.display(),
            super::BUILTIN.join(", ")
        )),
    }
}

fn vec3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

fn check_finite(path: &Path, element: &str, values: &[f32]) -> Result<(), String> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(format!("{}: {element}: values must be finite", path.display()))
    }
}

fn load_toml(path: &Path) -> Result<Scene, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let file: SceneFile = toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut materials = Vec::new();
    let mut index = BTreeMap::new();
    for (name, m) in &file.materials {
        let element = format!("materials.{name}");
        let m = match *m {
            MaterialFile::Diffuse { albedo } => Material::Diffuse { albedo: vec3(albedo) },
            MaterialFile::Mirror { tint, bump, bump_wavelength } => {
                let (delta, wavelength) = (bump.unwrap_or(0.0), bump_wavelength.unwrap_or(1.0));
                if !(0.0..=0.5).contains(&delta) {
                    return Err(format!("{}: {element}.bump must be an angle from 0 to 0.5 radians", path.display()));
                }
                if !(wavelength > 0.0 && wavelength.is_finite()) {
                    return Err(format!("{}: {element}.bump_wavelength must be a positive number", path.display()));
                }
                Material::Mirror { tint: vec3(tint.unwrap_or([1.0; 3])), bump: Bump { delta, wavelength } }
            }
            MaterialFile::Glass { ior } => {
                if !(ior > 0.0 && ior.is_finite()) {
                    return Err(format!("{}: {element}.ior must be a positive number", path.display()));
                }
                Material::Glass { ior }
            }
            MaterialFile::Glossy { albedo, variance } => {
                if !(variance >= 0.0 && variance.is_finite()) {
                    return Err(format!("{}: {element}.variance must be ≥ 0", path.display()));
                }
                Material::Glossy { albedo: vec3(albedo), variance }
            }
            MaterialFile::ThinGlass { tint, sigma } => {
                let sigma = sigma.unwrap_or(0.0);
                if !(sigma >= 0.0 && sigma.is_finite()) {
                    return Err(format!("{}: {element}.sigma must be ≥ 0", path.display()));
                }
                Material::ThinGlass { tint: vec3(tint), sigma }
            }
            MaterialFile::Emissive { radiance } => Material::Emissive { radiance: vec3(radiance) },
        };
        index.insert(name.clone(), materials.len() as u32);
        materials.push(m);
    }
    let mut triangles: Vec<(Triangle, u32)> = Vec::new();
    for (i, m) in file.meshes.iter().enumerate() {
        let element = format!("meshes[{i}]");
        let &mat = index
            .get(&m.material)
            .ok_or_else(|| format!("{}: {element}.material: no material named `{}`", path.display(), m.material))?;
        let scale = match m.scale {
            None => Vec3::ONE,
            Some(Scale::Uniform(s)) => Vec3::splat(s),
            Some(Scale::Axes(a)) => vec3(a),
        };
        let r = m.rotate.map_or(Vec3::ZERO, vec3);
        let t = m.translate.map_or(Vec3::ZERO, vec3);
        check_finite(
            path,
            &format!("{element} transform"),
            &[scale.x, scale.y, scale.z, r.x, r.y, r.z, t.x, t.y, t.z],
        )?;
        let rot = Mat3::from_euler(EulerRot::XYZ, r.x.to_radians(), r.y.to_radians(), r.z.to_radians());
        let mesh = load_obj(&dir.join(&m.file)).map_err(|e| format!("{}: {element}: {e}", path.display()))?;
        for tri in mesh.triangles() {
            triangles.push((Triangle { v: tri.v.map(|v| rot * (v * scale) + t) }, mat));
        }
    }
    let mut lights = Vec::new();
    for (i, l) in file.lights.iter().enumerate() {
        let element = format!("lights[{i}]");
        let light = match *l {
            LightFile::Point { position, intensity } => {
                Light::Point { position: vec3(position), intensity: vec3(intensity) }
            }
            LightFile::Quad { corner, edge_u, edge_v, radiance } => Light::Quad {
                corner: vec3(corner),
                edge_u: vec3(edge_u),
                edge_v: vec3(edge_v),
                radiance: vec3(radiance),
            },
            LightFile::Triangle { vertices, radiance } => {
                Light::Triangle { v: vertices.map(vec3), radiance: vec3(radiance) }
            }
        };
        let pts = light.polygon();
        check_finite(
            path,
            &element,
            &pts.iter().flat_map(|p| p.to_array()).chain(light.power().to_array()).collect::<Vec<_>>(),
        )?;
        if !matches!(light, Light::Point { .. }) && !(light.area() > 0.0) {
            return Err(format!("{}: {element}: the area light has zero area", path.display()));
        }
        lights.push(light);
    }
    let bounds = valid_bounds(path, &triangles)?;
    if lights.is_empty() {
        lights.push(default_light(bounds));
    }
    let camera = match file.camera {
        Some(c) => {
            check_finite(path, "camera", &[c.position, c.target, c.up.unwrap_or([0.0, 1.0, 0.0])].concat())?;
            let cam = Camera {
                position: vec3(c.position),
                target: vec3(c.target),
                up: vec3(c.up.unwrap_or([0.0, 1.0, 0.0])),
                fov_y: c.fov.unwrap_or(45.0),
                width: c.width.unwrap_or(512),
                height: c.height.unwrap_or(512),
            };
            if !(cam.fov_y > 0.0 && cam.fov_y < 180.0)
                || cam.width == 0
                || cam.height == 0
                || cam.position == cam.target
            {
                return Err(format!(
                    "{}: camera: needs 0 < fov < 180, a non-zero resolution and position ≠ target",
                    path.display()
                ));
            }
            cam
        }
        None => default_camera(bounds),
    };
    Ok(Scene::new(path.display().to_string(), triangles, materials, lights, camera))
}

/// Bounds of the non-degenerate triangles; an error naming the file when there is none.
fn valid_bounds(path: &Path, triangles: &[(Triangle, u32)]) -> Result<beam_math::Aabb, String> {
    let bounds = triangles
        .iter()
        .filter(|(t, _)| t.is_valid())
        .fold(beam_math::Aabb::EMPTY, |b, (t, _)| b.grow(t.v[0]).grow(t.v[1]).grow(t.v[2]));
    if bounds.is_valid() { Ok(bounds) } else { Err(format!("{}: no valid triangle", path.display())) }
}

/// A camera in front of the box (along +z), framing it.
fn default_camera(b: beam_math::Aabb) -> Camera {
    let c = b.center();
    let r = 0.5 * b.extent().length();
    Camera {
        position: c + Vec3::new(0.0, 0.2 * r, 2.4 * r),
        target: c,
        up: Vec3::Y,
        fov_y: 45.0,
        width: 512,
        height: 512,
    }
}

/// A downward-facing quad light above the box, a quarter of its width.
fn default_light(b: beam_math::Aabb) -> Light {
    let e = b.extent();
    let size = 0.25 * e.x.max(e.z);
    let corner = Vec3::new(b.center().x - 0.5 * size, b.max.y + 0.5 * e.y.max(0.1 * size), b.center().z - 0.5 * size);
    Light::Quad { corner, edge_u: Vec3::X * size, edge_v: Vec3::Z * size, radiance: Vec3::splat(20.0) }
}

fn load_bare_obj(path: &Path) -> Result<Scene, String> {
    let mesh = load_obj(path)?;
    let triangles: Vec<(Triangle, u32)> = mesh.triangles().into_iter().map(|t| (t, 0)).collect();
    let bounds = valid_bounds(path, &triangles)?;
    let materials = vec![Material::Diffuse { albedo: Vec3::splat(0.7) }];
    Ok(Scene::new(
        path.display().to_string(),
        triangles,
        materials,
        vec![default_light(bounds)],
        default_camera(bounds),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
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

    #[test]
    fn errors_name_the_file_and_line_or_element() {
        let dir = tempfile::tempdir().unwrap();
        let bad_syntax = write(dir.path(), "a.toml", "[camera]\nposition = [0, 0\n");
        let e = load_file(&bad_syntax).err().unwrap();
        assert!(e.contains("a.toml") && e.contains("line 2"), "{e}");
        let bad_material = write(dir.path(), "b.toml", "[[meshes]]\nfile = \"x.obj\"\nmaterial = \"nope\"\n");
        let e = load_file(&bad_material).err().unwrap();
        assert!(e.contains("b.toml") && e.contains("meshes[0].material"), "{e}");
        let zero_light = write(
            dir.path(),
            "c.toml",
            "[materials.w]\ntype=\"diffuse\"\nalbedo=[1,1,1]\n[[meshes]]\nfile=\"t.obj\"\nmaterial=\"w\"\n[[lights]]\ntype=\"quad\"\ncorner=[0,0,0]\nedge_u=[1,0,0]\nedge_v=[2,0,0]\nradiance=[1,1,1]\n",
        );
        write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let e = load_file(&zero_light).err().unwrap();
        assert!(e.contains("lights[0]") && e.contains("zero area"), "{e}");
        let bad_obj = write(dir.path(), "d.obj", "v 0 0 0\nv 1 x 0\nf 1 2 3\n");
        let e = load_file(&bad_obj).err().unwrap();
        assert!(e.contains("d.obj:2"), "{e}");
    }

    #[test]
    fn bare_obj_gets_a_camera_and_light() {
        let dir = tempfile::tempdir().unwrap();
        let p = write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let s = load(p.to_str().unwrap()).unwrap();
        assert_eq!(s.lights.len(), 1);
        assert!(s.camera.position.z > 0.5);
    }
}
