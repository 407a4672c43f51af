//! One glTF mesh primitive as an indexed triangle mesh: its positions (finite), and its triangles,
//! strips or fans as index triples (each index checked against the positions).

use super::accessor;
use crate::mesh::Mesh;
use beam_math::glam::Vec3;
use gltf::accessor::Dimensions;
use gltf::mesh::Mode;
use std::rc::Rc;

/// The mesh of primitive `p` in its mesh's space, or `None` for a point or line primitive (which
/// has no area to render). Errors say what is wrong; the caller names the primitive.
pub(super) fn triangles(p: &gltf::Primitive, buffers: &[Rc<Vec<u8>>]) -> Result<Option<Mesh>, String> {
    let mode = p.mode();
    if matches!(mode, Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip) {
        return Ok(None);
    }
    let Some(position) = p.get(&gltf::Semantic::Positions) else {
        return Err("has no POSITION attribute".into());
    };
    if position.dimensions() != Dimensions::Vec3 {
        return Err(format!("POSITION accessor {}: must be VEC3, not {:?}", position.index(), position.dimensions()));
    }
    let xyz = accessor::floats(&position, buffers)?;
    if let Some(i) = xyz.iter().position(|x| !x.is_finite()) {
        return Err(format!("POSITION {} is not finite: {:?}", i / 3, &xyz[i / 3 * 3..i / 3 * 3 + 3]));
    }
    let positions: Vec<Vec3> = xyz.chunks_exact(3).map(Vec3::from_slice).collect();
    let order = match p.indices() {
        Some(a) => accessor::indices(&a, buffers)?,
        None => (0..positions.len() as u32).collect(),
    };
    if let Some(&i) = order.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(format!("index {i} out of range ({} vertices)", positions.len()));
    }
    let n = order.len();
    let indices: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|k| {
                // Every other triangle of a strip is wound the other way round (glTF 2.0 §3.7.2.1).
                if k % 2 == 0 { [order[k], order[k + 1], order[k + 2]] } else { [order[k], order[k + 2], order[k + 1]] }
            })
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1)).map(|k| [order[k], order[k + 1], order[0]]).collect(),
        _ => order.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    };
    Ok(Some(Mesh { positions, indices }))
}
