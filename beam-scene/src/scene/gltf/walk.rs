//! The node hierarchy of a glTF scene walked from its roots, each node's matrix composed with its
//! parents': its mesh's triangles in world space (emissive ones also as triangle lights), its
//! camera and its `KHR_lights_punctual` light.

use super::{MAX_GLTF_TRIANGLES, error, primitive};
use crate::error::SceneError;
use crate::mesh::Mesh;
use crate::scene::{Camera, Light, Material};
use beam_math::Triangle;
use beam_math::glam::{Mat4, Quat, Vec3};
use gltf::json::validation::Checked;
use gltf::khr_lights_punctual::Kind;
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::path::Path;
use std::rc::Rc;

/// What the walk found.
pub(super) struct Walked {
    /// Triangles in world space with their material (degenerate ones included).
    pub triangles: Vec<(Triangle, u32)>,
    /// Point lights (from point and spot lights) and one triangle light per emissive triangle.
    pub lights: Vec<Light>,
    /// The camera of the lowest-numbered perspective camera a node places, if any.
    pub camera: Option<Camera>,
    /// Point and line primitives skipped (once per mesh).
    pub skipped_primitives: usize,
    /// Directional lights skipped (we have none).
    pub skipped_lights: usize,
}

/// Walk the default scene of `document` (else its first scene, else every node without a parent):
/// each node's world matrix is its parents' times its own (`matrix`, or translation × rotation ×
/// scale). A node reached twice (a cycle, or a node with two parents) is an error, so the walk ends.
pub(super) fn walk(
    path: &Path,
    document: &gltf::Document,
    buffers: &[Rc<Vec<u8>>],
    materials: &[Material],
) -> Result<Walked, SceneError> {
    let roots: Vec<gltf::Node> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut child = vec![false; document.nodes().len()];
            document.nodes().flat_map(|n| n.children()).for_each(|c| child[c.index()] = true);
            document.nodes().filter(|n| !child[n.index()]).collect()
        }
    };
    let mut walked =
        Walked { triangles: Vec::new(), lights: Vec::new(), camera: None, skipped_primitives: 0, skipped_lights: 0 };
    let mut camera_index = usize::MAX;
    let mut meshes: HashMap<usize, Vec<(Mesh, u32)>> = HashMap::new();
    let mut seen = vec![false; document.nodes().len()];
    let mut stack: Vec<(gltf::Node, Mat4)> = roots.into_iter().rev().map(|n| (n, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        let element = format!("node {}", node.index());
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(error(path, element, "reached twice in the node hierarchy (glTF nodes form trees)"));
        }
        let world = parent * local_matrix(path, &element, &node)?;
        if !world.is_finite() {
            return Err(error(path, element, "its world matrix overflows (values must stay finite)"));
        }
        if let Some(mesh) = node.mesh() {
            let parts = match meshes.entry(mesh.index()) {
                Entry::Occupied(e) => e.into_mut(),
                Entry::Vacant(e) => {
                    let (parts, skipped) = read_mesh(path, &mesh, buffers, materials.len() - 1)?;
                    walked.skipped_primitives += skipped;
                    e.insert(parts)
                }
            };
            place(path, &element, parts, world, materials, &mut walked)?;
        }
        if let Some(c) = node.camera().filter(|c| c.index() < camera_index) {
            if let Some(cam) = camera(path, document, c.index(), world)? {
                (walked.camera, camera_index) = (Some(cam), c.index());
            }
        }
        if let Some(light) = node.light() {
            let position = world.transform_point3(Vec3::ZERO);
            let intensity = Vec3::from_array(light.color()) * light.intensity();
            if !(intensity.is_finite() && intensity.min_element() >= 0.0) {
                return Err(error(
                    path,
                    format!("light {}", light.index()),
                    "color × intensity must be finite and ≥ 0",
                ));
            }
            match light.kind() {
                // A spot light becomes a point light of its intensity: the cone is not kept.
                Kind::Point | Kind::Spot { .. } => walked.lights.push(Light::Point { position, intensity }),
                Kind::Directional => walked.skipped_lights += 1,
            }
        }
        stack.extend(node.children().map(|c| (c, world)).collect::<Vec<_>>().into_iter().rev());
    }
    Ok(walked)
}

/// The matrix of `node` relative to its parent, its values checked finite (and a rotation
/// quaternion of non-zero length, normalized).
fn local_matrix(path: &Path, element: &str, node: &gltf::Node) -> Result<Mat4, SceneError> {
    let m = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => Mat4::from_cols_array_2d(&matrix),
        gltf::scene::Transform::Decomposed { translation, rotation, scale } => {
            let q = Quat::from_array(rotation);
            if !(q.length_squared() > 0.0 && q.is_finite()) {
                return Err(error(path, element, format!("rotation {rotation:?} is not a unit quaternion")));
            }
            Mat4::from_scale_rotation_translation(scale.into(), q.normalize(), translation.into())
        }
    };
    if m.is_finite() { Ok(m) } else { Err(error(path, element, "its transform values must be finite")) }
}

/// The triangle meshes of `mesh`'s primitives with their material index (`default` for none), and
/// how many point and line primitives were skipped.
fn read_mesh(
    path: &Path,
    mesh: &gltf::Mesh,
    buffers: &[Rc<Vec<u8>>],
    default: usize,
) -> Result<(Vec<(Mesh, u32)>, usize), SceneError> {
    let (mut parts, mut skipped) = (Vec::new(), 0);
    for p in mesh.primitives() {
        let element = format!("mesh {} primitive {}", mesh.index(), p.index());
        match primitive::triangles(&p, buffers).map_err(|e| error(path, element, e))? {
            Some(m) => parts.push((m, p.material().index().unwrap_or(default) as u32)),
            None => skipped += 1,
        }
    }
    Ok((parts, skipped))
}

/// Add the triangles of a node's mesh `parts` under its world matrix `world` (winding kept
/// counter-clockwise from the front when `world` mirrors), and a triangle light for each
/// non-degenerate emissive one.
fn place(
    path: &Path,
    element: &str,
    parts: &[(Mesh, u32)],
    world: Mat4,
    materials: &[Material],
    walked: &mut Walked,
) -> Result<(), SceneError> {
    let count: usize = parts.iter().map(|(m, _)| m.indices.len()).sum();
    if walked.triangles.len() + count > MAX_GLTF_TRIANGLES {
        return Err(error(path, element, format!("the scene has more than {MAX_GLTF_TRIANGLES} triangles")));
    }
    let mirrored = world.determinant() < 0.0;
    for (mesh, material) in parts {
        let emissive = match materials[*material as usize] {
            Material::Emissive { radiance } => Some(radiance),
            _ => None,
        };
        for t in &mesh.indices {
            // Through the indices, so that the work follows the triangles placed (bounded above),
            // not the vertices of a mesh that many nodes place with few triangles.
            let [a, b, c] = t.map(|i| world.transform_point3(mesh.positions[i as usize]));
            let tri = if mirrored { Triangle::new(a, c, b) } else { Triangle::new(a, b, c) };
            if let (Some(radiance), true) = (emissive, tri.is_valid()) {
                walked.lights.push(Light::Triangle { v: tri.v, radiance });
            }
            walked.triangles.push((tri, *material));
        }
    }
    Ok(())
}

/// Our camera for glTF camera `index` placed by `world` (it looks down its local −z with +y up):
/// vertical field of view from `yfov`, 512 pixels high and as wide as its aspect ratio says
/// (square without one); `None` for an orthographic camera.
fn camera(path: &Path, document: &gltf::Document, index: usize, world: Mat4) -> Result<Option<Camera>, SceneError> {
    let element = format!("camera {index}");
    let json = document.as_json().cameras.get(index);
    let perspective = json.filter(|c| c.type_ == Checked::Valid(gltf::json::camera::Type::Perspective));
    let Some(p) = perspective.and_then(|c| c.perspective.as_ref()) else {
        return Ok(None);
    };
    let fov_y = p.yfov.to_degrees();
    if !(fov_y > 0.0 && fov_y < 180.0) {
        return Err(error(path, element, format!("yfov {} must lie between 0 and π", p.yfov)));
    }
    let aspect = p.aspect_ratio.unwrap_or(1.0);
    if !(aspect > 0.0 && aspect.is_finite()) {
        return Err(error(path, element, format!("aspectRatio {aspect} must be a positive number")));
    }
    let position = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let up = world.transform_vector3(Vec3::Y);
    if forward == Vec3::ZERO || !(up.cross(forward).length_squared() > 0.0) {
        return Err(error(path, element, "its node's transform collapses the view direction or up vector"));
    }
    let height = 512;
    let width = (height as f32 * aspect).round().clamp(1.0, 4096.0) as u32;
    Ok(Some(Camera { position, target: position + forward, up, fov_y, width, height }))
}
