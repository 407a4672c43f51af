//! `EXT_mesh_gpu_instancing`: the matrices of a node's instances, each translation × rotation ×
//! scale from its attribute accessors (each optional, all of one count), to be composed after the
//! node's world matrix.

use super::accessor;
use super::raw::Instancing;
use beam_math::glam::{Mat4, Quat, Vec3};
use gltf::accessor::Dimensions;
use std::rc::Rc;

/// The instance matrices of `attributes`, or `None` when it names no accessor (the node's mesh is
/// then placed once). Errors say what is wrong; the caller names the node.
pub(super) fn matrices(
    document: &gltf::Document,
    buffers: &[Rc<Vec<u8>>],
    attributes: &Instancing,
) -> Result<Option<Vec<Mat4>>, String> {
    let read = |name: &str, index: Option<usize>, dimensions: Dimensions| -> Result<Option<Vec<f32>>, String> {
        let Some(index) = index else {
            return Ok(None);
        };
        let at = format!("EXT_mesh_gpu_instancing {name}");
        let a = document.accessors().nth(index).ok_or_else(|| format!("{at}: accessor {index} does not exist"))?;
        if a.dimensions() != dimensions {
            return Err(format!("{at}: accessor {index} must be {dimensions:?}, not {:?}", a.dimensions()));
        }
        let values = accessor::floats(&a, buffers)?;
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            return Err(format!("{at}: instance {} is not finite", i / dimensions.multiplicity()));
        }
        Ok(Some(values))
    };
    let translation = read("TRANSLATION", attributes.translation, Dimensions::Vec3)?;
    let rotation = read("ROTATION", attributes.rotation, Dimensions::Vec4)?;
    let scale = read("SCALE", attributes.scale, Dimensions::Vec3)?;
    let counts = [(&translation, 3), (&rotation, 4), (&scale, 3)].map(|(v, n)| v.as_ref().map(|v| v.len() / n));
    let Some(count) = counts.iter().flatten().next().copied() else {
        return Ok(None);
    };
    if counts.iter().flatten().any(|&c| c != count) {
        return Err(format!("EXT_mesh_gpu_instancing: its attributes have different counts ({counts:?})"));
    }
    (0..count)
        .map(|i| {
            let t = translation.as_ref().map_or(Vec3::ZERO, |v| Vec3::from_slice(&v[3 * i..]));
            let s = scale.as_ref().map_or(Vec3::ONE, |v| Vec3::from_slice(&v[3 * i..]));
            let q = rotation.as_ref().map_or(Quat::IDENTITY, |v| Quat::from_slice(&v[4 * i..]));
            if !(q.length_squared() > 0.0) {
                return Err(format!("EXT_mesh_gpu_instancing ROTATION: instance {i} is not a unit quaternion"));
            }
            Ok(Mat4::from_scale_rotation_translation(s, q.normalize(), t))
        })
        .collect::<Result<_, _>>()
        .map(Some)
}
