//! What a scene file (TOML) may say, and the checked values it gives.
//!
//! ```toml
//! [camera]                      # optional for a scene made of one mesh
//! position = [0, 1, 4]          # a still camera (or [[camera.keys]] below, not both)
//! target = [0, 1, 0]
//! up = [0, 1, 0]                # default [0, 1, 0]
//! fov = 45                      # vertical, degrees; default 45
//! width = 512                   # default 512
//! height = 512                  # default 512
//!
//! [[camera.keys]]               # an animated camera (`beam render --frame K`): keyframes in
//! frame = 0                     # increasing frame order, linearly interpolated; frames run from 0
//! position = [0, 1, 4]          # to the last key's (held at the first key before it)
//! target = [0, 1, 0]
//!
//! [materials.white]             # type: diffuse | mirror | glass | glossy | emissive
//! type = "diffuse"
//! albedo = [0.7, 0.7, 0.7]
//!
//! [[meshes]]
//! file = "bunny.obj"            # relative to this file's folder, and inside it
//! material = "white"
//! translate = [0, 0, 0]         # optional transform: scale, then rotate (degrees about x, y, z), then translate
//! rotate = [0, 90, 0]
//! scale = 1.0                   # a number or [x, y, z]
//!
//! smesh = "bunny-coarse.obj"    # mirror or glass only, optional: a coarse S mesh (000 §7.1) for
//!                               # the nonlinear beams, in the mesh's own coordinates (transformed
//!                               # with it); or smesh_target = 300 (faces) or smesh_error = 0.01
//!                               # (a fraction of its size): the mesh simplified by meshoptimizer
//!
//! [smesh]                       # optional: simplify every other mirror and glass mesh for the
//! target = 1500                 # nonlinear beams to about this many S-mesh faces in all,
//!                               # or `error = 0.01`
//!
//! [[lights]]                    # type: point | quad | triangle
//! type = "quad"
//! corner = [-0.5, 2, -0.5]
//! edge_u = [1, 0, 0]
//! edge_v = [0, 0, 1]
//! radiance = [10, 10, 10]       # intensity for a point light
//!
//! [environment]                 # optional: what rays leaving the scene see, and its light (default black)
//! color = [0.3, 0.33, 0.38]     # a uniform sky of this radiance, or
//! map = "sky.hdr"               # an equirectangular map, .hdr or .exr (+Y up, +X at its centre column)
//! intensity = 1.0               # optional: scales the colour or the map
//! rotation = 0                  # optional, a map only: degrees about +Y
//! ```

use super::camera::Camera;
use super::camera_path::{CameraKey, CameraPath};
use super::check::{colour, finite};
use super::light::Light;
use super::material::{Bump, Material};
use crate::error::SceneError;
use beam_math::glam::Vec3;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    pub(super) camera: Option<CameraFile>,
    #[serde(default)]
    pub(super) materials: BTreeMap<String, MaterialFile>,
    #[serde(default)]
    pub(super) meshes: Vec<MeshFile>,
    #[serde(default)]
    pub(super) lights: Vec<LightFile>,
    pub(super) smesh: Option<SMeshFile>,
    pub(super) environment: Option<EnvironmentFile>,
}

/// The environment (`[environment]`): a colour or a map file, checked by
/// [`super::environment_file`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EnvironmentFile {
    pub(super) color: Option<[f32; 3]>,
    pub(super) map: Option<String>,
    pub(super) intensity: Option<f32>,
    pub(super) rotation: Option<f32>,
}

/// The scene-wide S-mesh simplification (`[smesh]`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SMeshFile {
    pub(super) target: Option<u32>,
    pub(super) error: Option<f32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraFile {
    pub(super) position: Option<[f32; 3]>,
    pub(super) target: Option<[f32; 3]>,
    #[serde(default)]
    pub(super) keys: Vec<CameraKeyFile>,
    pub(super) up: Option<[f32; 3]>,
    pub(super) fov: Option<f32>,
    pub(super) width: Option<u32>,
    pub(super) height: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraKeyFile {
    pub(super) frame: u32,
    pub(super) position: [f32; 3],
    pub(super) target: [f32; 3],
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub(super) enum MaterialFile {
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
pub(super) enum Scale {
    Uniform(f32),
    Axes([f32; 3]),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshFile {
    pub(super) file: String,
    pub(super) material: String,
    pub(super) translate: Option<[f32; 3]>,
    pub(super) rotate: Option<[f32; 3]>,
    pub(super) scale: Option<Scale>,
    pub(super) smesh: Option<String>,
    pub(super) smesh_target: Option<u32>,
    pub(super) smesh_error: Option<f32>,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub(super) enum LightFile {
    Point { position: [f32; 3], intensity: [f32; 3] },
    Quad { corner: [f32; 3], edge_u: [f32; 3], edge_v: [f32; 3], radiance: [f32; 3] },
    Triangle { vertices: [[f32; 3]; 3], radiance: [f32; 3] },
}

/// Field `field` of `element` of the scene file `path` is not `expected`.
fn out_of_range(path: &Path, element: &str, field: &str, expected: &'static str) -> SceneError {
    SceneError::OutOfRange { path: path.to_path_buf(), element: format!("{element}.{field}"), expected }
}

fn vec3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

/// The material `element` of the scene file `path`, its values checked (colours finite and ≥ 0).
pub(super) fn material(path: &Path, element: &str, m: &MaterialFile) -> Result<Material, SceneError> {
    Ok(match *m {
        MaterialFile::Diffuse { albedo } => {
            colour(path, &format!("{element}.albedo"), albedo)?;
            Material::Diffuse { albedo: vec3(albedo) }
        }
        MaterialFile::Mirror { tint, bump, bump_wavelength } => {
            colour(path, &format!("{element}.tint"), tint.unwrap_or([1.0; 3]))?;
            let (delta, wavelength) = (bump.unwrap_or(0.0), bump_wavelength.unwrap_or(1.0));
            if !(0.0..=0.5).contains(&delta) {
                return Err(out_of_range(path, element, "bump", "an angle from 0 to 0.5 radians"));
            }
            if !(wavelength > 0.0 && wavelength.is_finite()) {
                return Err(out_of_range(path, element, "bump_wavelength", "a positive number"));
            }
            Material::Mirror { tint: vec3(tint.unwrap_or([1.0; 3])), bump: Bump { delta, wavelength } }
        }
        MaterialFile::Glass { ior } => {
            if !(ior > 0.0 && ior.is_finite()) {
                return Err(out_of_range(path, element, "ior", "a positive number"));
            }
            Material::Glass { ior }
        }
        MaterialFile::Glossy { albedo, variance } => {
            if !(variance >= 0.0 && variance.is_finite()) {
                return Err(out_of_range(path, element, "variance", "≥ 0"));
            }
            colour(path, &format!("{element}.albedo"), albedo)?;
            Material::Glossy { albedo: vec3(albedo), variance }
        }
        MaterialFile::ThinGlass { tint, sigma } => {
            let sigma = sigma.unwrap_or(0.0);
            if !(sigma >= 0.0 && sigma.is_finite()) {
                return Err(out_of_range(path, element, "sigma", "≥ 0"));
            }
            colour(path, &format!("{element}.tint"), tint)?;
            Material::ThinGlass { tint: vec3(tint), sigma }
        }
        MaterialFile::Emissive { radiance } => {
            colour(path, &format!("{element}.radiance"), radiance)?;
            Material::Emissive { radiance: vec3(radiance) }
        }
    })
}

/// The light `element` of the scene file `path`, checked: finite corners or position, a colour
/// finite and ≥ 0, an area light's area positive.
pub(super) fn light(path: &Path, element: &str, l: &LightFile) -> Result<Light, SceneError> {
    let light = match *l {
        LightFile::Point { position, intensity } => {
            finite(path, &format!("{element}.position"), &position)?;
            Light::Point { position: vec3(position), intensity: vec3(intensity) }
        }
        LightFile::Quad { corner, edge_u, edge_v, radiance } => {
            Light::Quad { corner: vec3(corner), edge_u: vec3(edge_u), edge_v: vec3(edge_v), radiance: vec3(radiance) }
        }
        LightFile::Triangle { vertices, radiance } => {
            Light::Triangle { v: vertices.map(vec3), radiance: vec3(radiance) }
        }
    };
    let pts = light.polygon();
    finite(path, element, &pts.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>())?;
    let what = if matches!(light, Light::Point { .. }) { "intensity" } else { "radiance" };
    colour(path, &format!("{element}.{what}"), light.power().to_array())?;
    if !matches!(light, Light::Point { .. }) && !(light.area() > 0.0) {
        return Err(SceneError::Invalid {
            path: path.to_path_buf(),
            element: element.to_string(),
            message: "the area light has zero area".into(),
        });
    }
    Ok(light)
}

/// The camera of the scene file `path` and its path when it has `[[camera.keys]]`, checked:
/// finite, and a view at every key ([`Camera::check_view`]: 0 < fov < 180, a non-zero resolution, an
/// up vector not along the view, a view of non-zero length, an eye that 32-bit floats can place);
/// keys in strictly increasing frame order. The camera is frame 0's.
pub(super) fn camera(path: &Path, c: &CameraFile) -> Result<(Camera, Option<CameraPath>), SceneError> {
    let invalid = |element: &str, message: String| SceneError::Invalid {
        path: path.to_path_buf(),
        element: element.to_string(),
        message,
    };
    let (position, target) = match (c.position, c.target, c.keys.first()) {
        (Some(p), Some(t), None) => (p, t),
        (None, None, Some(k)) => (k.position, k.target),
        (_, _, None) => return Err(invalid("camera", "needs position and target, or [[camera.keys]]".into())),
        (_, _, Some(_)) => {
            return Err(invalid(
                "camera",
                "give position and target (a still camera) or [[camera.keys]] (an animated one), not both".into(),
            ));
        }
    };
    let up = c.up.unwrap_or([0.0, 1.0, 0.0]);
    finite(path, "camera", &[position, target, up].concat())?;
    let cam = Camera {
        position: vec3(position),
        target: vec3(target),
        up: vec3(up),
        fov_y: c.fov.unwrap_or(45.0),
        width: c.width.unwrap_or(512),
        height: c.height.unwrap_or(512),
    };
    cam.check_view().map_err(|why| invalid("camera", why))?;
    let mut keys = Vec::with_capacity(c.keys.len());
    for (i, k) in c.keys.iter().enumerate() {
        let element = format!("camera.keys[{i}]");
        finite(path, &element, &[k.position, k.target].concat())?;
        let key = CameraKey { frame: k.frame, position: vec3(k.position), target: vec3(k.target) };
        (Camera { position: key.position, target: key.target, ..cam })
            .check_view()
            .map_err(|why| invalid(&element, why))?;
        if let Some(before) = keys.last().filter(|b: &&CameraKey| b.frame >= key.frame) {
            return Err(invalid(
                &format!("{element}.frame {}", key.frame),
                format!("frames must increase (camera.keys[{}] has frame {})", i - 1, before.frame),
            ));
        }
        keys.push(key);
    }
    let camera_path = CameraPath::new(keys);
    let cam = camera_path.as_ref().and_then(|p| p.camera_at(&cam, 0)).unwrap_or(cam);
    Ok((cam, camera_path))
}
