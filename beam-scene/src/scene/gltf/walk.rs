//! The node hierarchy of a glTF scene walked from its roots, each node's matrix composed with its
//! parents': its mesh's triangles in world space (emissive ones also as triangle lights), once per
//! `EXT_mesh_gpu_instancing` instance when it has them ([`instancing`]), its camera ([`camera`])
//! and its `KHR_lights_punctual` light. Morph targets are applied under the node's (else the
//! mesh's) default weights; skins are not applied, only counted.

use super::errors::error;
use super::primitive::{self, Part};
use super::raw::Instancing;
use super::{camera, instancing};
use crate::error::SceneError;
use crate::scene::camera::Camera;
use crate::scene::light::Light;
use crate::scene::material::Material;
use crate::scene::surface::Surfaces;
use beam_math::Triangle;
use beam_math::glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::khr_lights_punctual::Kind;
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::path::Path;
use std::rc::Rc;

/// Most triangles a glTF scene may expand to once meshes are instanced by their nodes (a small
/// file may place a large mesh many times): 2²⁵, about 1.3 GiB of placed triangles before the
/// BVH, so that a few kilobytes of JSON cannot take the machine's memory before `beam render`'s
/// memory estimate is made. Sixty times the Sponza atrium.
const MAX_GLTF_TRIANGLES: usize = 1 << 25;

/// A mesh read under morph weights: its index and the weights' bits (empty without targets).
type MeshKey = (usize, Vec<u32>);

/// What the walk found.
pub(super) struct Walked {
    /// Triangles in world space with their material (degenerate ones included).
    pub triangles: Vec<(Triangle, u32)>,
    /// Point lights (from point and spot lights) and one triangle light per emissive triangle.
    pub lights: Vec<Light>,
    /// The camera of the lowest-numbered camera a node places, if any.
    pub camera: Option<Camera>,
    /// Whether that camera approximates an orthographic one.
    pub orthographic: bool,
    /// Skins of the meshes placed (not applied: meshes are drawn in their bind pose).
    pub skins: usize,
    /// Texture coordinates and colours of the triangles' corners, with the materials' textures.
    pub surfaces: Surfaces,
    /// Point and line primitives skipped (once per mesh).
    pub skipped_primitives: usize,
    /// Directional lights skipped (we have none).
    pub skipped_lights: usize,
    /// Spot lights placed as point lights (their cone is not kept).
    pub spot_lights: usize,
}

/// Walk the default scene of `document` (else its first scene, else every node without a parent):
/// each node's world matrix is its parents' times its own (`matrix`, or translation × rotation ×
/// scale). A node reached twice (a cycle, or a node with two parents) is an error, so the walk ends.
pub(super) fn walk(
    path: &Path,
    document: &gltf::Document,
    buffers: &[Rc<Vec<u8>>],
    materials: &[Material],
    instanced: &HashMap<usize, Instancing>,
    surfaces: Surfaces,
) -> Result<Walked, SceneError> {
    let roots: Vec<gltf::Node> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut child = vec![false; document.nodes().len()];
            document.nodes().flat_map(|n| n.children()).for_each(|c| child[c.index()] = true);
            document.nodes().filter(|n| !child[n.index()]).collect()
        }
    };
    let mut walked = Walked {
        triangles: Vec::new(),
        lights: Vec::new(),
        camera: None,
        surfaces,
        orthographic: false,
        skins: 0,
        skipped_primitives: 0,
        skipped_lights: 0,
        spot_lights: 0,
    };
    let mut skinned = vec![false; document.skins().len()];
    let mut camera_index = usize::MAX;
    let mut meshes: HashMap<MeshKey, Vec<(Part, u32)>> = HashMap::new();
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
            let targets = mesh.primitives().any(|p| p.morph_targets().len() > 0);
            let weights = if targets { node.weights().or(mesh.weights()).unwrap_or_default() } else { &[] };
            if let Some(w) = weights.iter().find(|w| !w.is_finite()) {
                return Err(error(path, element, format!("morph weight {w} is not finite")));
            }
            let key = (mesh.index(), weights.iter().map(|w| w.to_bits()).collect());
            let parts = match meshes.entry(key) {
                Entry::Occupied(e) => e.into_mut(),
                Entry::Vacant(e) => {
                    let (parts, skipped) = read_mesh(path, &mesh, buffers, weights, materials.len() - 1)?;
                    walked.skipped_primitives += skipped;
                    e.insert(parts)
                }
            };
            let instances = match instanced.get(&node.index()) {
                Some(attributes) => {
                    instancing::matrices(document, buffers, attributes).map_err(|e| error(path, &element, e))?
                }
                None => None,
            };
            match instances {
                Some(instances) => {
                    for m in instances {
                        place(path, &element, parts, world * m, materials, &mut walked)?;
                    }
                }
                None => place(path, &element, parts, world, materials, &mut walked)?,
            }
            if let Some(skin) = node.skin() {
                walked.skins += usize::from(!std::mem::replace(&mut skinned[skin.index()], true));
            }
        }
        if let Some(c) = node.camera().filter(|c| c.index() < camera_index) {
            if let Some((cam, orthographic)) = camera::camera(path, document, c.index(), world)? {
                (walked.camera, walked.orthographic, camera_index) = (Some(cam), orthographic, c.index());
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
                Kind::Point => walked.lights.push(Light::Point { position, intensity }),
                // A spot light becomes a point light of its intensity: the cone is not kept.
                Kind::Spot { .. } => {
                    walked.lights.push(Light::Point { position, intensity });
                    walked.spot_lights += 1;
                }
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

/// The triangle meshes of `mesh`'s primitives under the morph `weights` with their material index
/// (`default` for none), and how many point and line primitives were skipped.
fn read_mesh(
    path: &Path,
    mesh: &gltf::Mesh,
    buffers: &[Rc<Vec<u8>>],
    weights: &[f32],
    default: usize,
) -> Result<(Vec<(Part, u32)>, usize), SceneError> {
    let (mut parts, mut skipped) = (Vec::new(), 0);
    for p in mesh.primitives() {
        let element = format!("mesh {} primitive {}", mesh.index(), p.index());
        match primitive::triangles(&p, buffers, weights).map_err(|e| error(path, element, e))? {
            Some(m) => parts.push((m, p.material().index().unwrap_or(default) as u32)),
            None => skipped += 1,
        }
    }
    Ok((parts, skipped))
}

/// Add the triangles of a node's mesh `parts` under its world matrix `world` (winding kept
/// counter-clockwise from the front when `world` mirrors) with their corners' texture coordinates
/// and colours, and a triangle light for each non-degenerate emissive one (of its emissive
/// texture's mean radiance over the triangle; none where that is black).
fn place(
    path: &Path,
    element: &str,
    parts: &[(Part, u32)],
    world: Mat4,
    materials: &[Material],
    walked: &mut Walked,
) -> Result<(), SceneError> {
    let count: usize = parts.iter().map(|(m, _)| m.mesh.indices.len()).sum();
    if walked.triangles.len() + count > MAX_GLTF_TRIANGLES {
        return Err(error(path, element, format!("the scene has more than {MAX_GLTF_TRIANGLES} triangles")));
    }
    let mirrored = world.determinant() < 0.0;
    for (part, material) in parts {
        let emissive = match materials[*material as usize] {
            Material::Emissive { radiance } => Some(radiance),
            _ => None,
        };
        let mesh = &part.mesh;
        // Normals go by the inverse transpose (unit length again where it scales).
        let to_world = Mat3::from_mat4(world).inverse().transpose();
        let normals: Vec<Vec3> = part.normal.iter().map(|&n| (to_world * n).normalize_or_zero()).collect();
        for t in &mesh.indices {
            // Through the indices, so that the work follows the triangles placed (bounded above),
            // not the vertices of a mesh that many nodes place with few triangles.
            let t = if mirrored { [t[0], t[2], t[1]] } else { *t };
            let tri = Triangle { v: t.map(|i| world.transform_point3(mesh.positions[i as usize])) };
            let at = walked.triangles.len();
            let s = &mut walked.surfaces;
            for set in 0..2 {
                corners(&mut s.uv[set], &part.uv[set], t, at, Vec2::ZERO);
            }
            corners(&mut s.color, &part.color, t, at, Vec4::ONE);
            corners(&mut s.normals, &normals, t, at, Vec3::ZERO);
            if let (Some(radiance), true) = (emissive, tri.is_valid()) {
                let radiance = radiance * s.mean_emissive_factor(at as u32, *material);
                if radiance.max_element() > 0.0 {
                    walked.lights.push(Light::Triangle { v: tri.v, radiance });
                }
            }
            walked.triangles.push((tri, *material));
        }
    }
    Ok(())
}

/// Append to the per-triangle list `list` (now covering the first `at` triangles, or empty) the
/// attribute `values` at the corners `t`: when the part has none, `none` at each corner (nothing
/// while the list is empty); the first part with values fills the earlier triangles with `none`.
fn corners<T: Copy>(list: &mut Vec<[T; 3]>, values: &[T], t: [u32; 3], at: usize, none: T) {
    if values.is_empty() {
        if !list.is_empty() {
            list.push([none; 3]);
        }
        return;
    }
    list.resize(at, [none; 3]);
    list.push(t.map(|i| values[i as usize]));
}
