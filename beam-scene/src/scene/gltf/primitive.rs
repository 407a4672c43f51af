//! One glTF mesh primitive as an indexed triangle mesh: its positions (finite), its triangles,
//! strips or fans as index triples (each index checked against the positions), and the vertex
//! attributes shading reads: texture coordinates `TEXCOORD_0` and `_1`, colours `COLOR_0`,
//! normals; positions and normals in the default pose of the morph targets.

use super::accessor;
use crate::mesh::Mesh;
use beam_math::glam::{Vec2, Vec3, Vec4};
use gltf::accessor::Dimensions;
use gltf::mesh::Mode;
use std::rc::Rc;

/// A primitive's triangles and the vertex attributes shading reads (each empty when absent, else
/// one per position).
pub(super) struct Part {
    /// Positions and triangles.
    pub mesh: Mesh,
    /// Texture coordinates of sets 0 and 1.
    pub uv: [Vec<Vec2>; 2],
    /// Linear RGBA vertex colours (`COLOR_0`; alpha 1 for RGB ones).
    pub color: Vec<Vec4>,
    /// Vertex normals (`NORMAL`, in the mesh's space; zero where not finite).
    pub normal: Vec<Vec3>,
}

/// The mesh of primitive `p` in its mesh's space with its attributes, or `None` for a point or
/// line primitive (which has no area to render), its morph targets applied under `weights` (the
/// node's or mesh's, one per target; missing ones 0). Errors say what is wrong; the caller names
/// the primitive.
pub(super) fn triangles(p: &gltf::Primitive, buffers: &[Rc<Vec<u8>>], weights: &[f32]) -> Result<Option<Part>, String> {
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
    let mut xyz = accessor::floats(&position, buffers)?;
    morph(p, buffers, weights, Target::Position, &mut xyz)?;
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
    let uv = [0, 1].map(|set| attribute(p, buffers, gltf::Semantic::TexCoords(set), positions.len()));
    let [uv0, uv1] = uv;
    let uv = [uv0?, uv1?].map(|v| v.chunks_exact(2).map(Vec2::from_slice).collect());
    let color = attribute(p, buffers, gltf::Semantic::Colors(0), positions.len())?;
    let channels = if positions.is_empty() { 4 } else { color.len() / positions.len() };
    let color = color
        .chunks_exact(channels.max(1))
        .map(|c| {
            let c = Vec4::new(
                c[0],
                c.get(1).copied().unwrap_or(0.0),
                c.get(2).copied().unwrap_or(0.0),
                c.get(3).copied().unwrap_or(1.0),
            );
            if c.is_finite() { c.clamp(Vec4::ZERO, Vec4::ONE) } else { Vec4::ONE }
        })
        .collect();
    if p.get(&gltf::Semantic::Normals).is_some_and(|a| a.dimensions() != Dimensions::Vec3) {
        return Err("its NORMAL attribute is not VEC3".into());
    }
    let mut normal = attribute(p, buffers, gltf::Semantic::Normals, positions.len())?;
    if !normal.is_empty() {
        morph(p, buffers, weights, Target::Normal, &mut normal)?;
    }
    let normal =
        normal.chunks_exact(3).map(Vec3::from_slice).map(|n| if n.is_finite() { n } else { Vec3::ZERO }).collect();
    Ok(Some(Part { mesh: Mesh { positions, indices }, uv, color, normal }))
}

/// The components of `p`'s attribute `semantic` (empty when it has none), checked to hold one
/// element per vertex of the `vertices`.
fn attribute(
    p: &gltf::Primitive,
    buffers: &[Rc<Vec<u8>>],
    semantic: gltf::Semantic,
    vertices: usize,
) -> Result<Vec<f32>, String> {
    let Some(a) = p.get(&semantic) else {
        return Ok(Vec::new());
    };
    if a.count() != vertices {
        return Err(format!("{semantic:?} accessor {}: {} elements for {vertices} vertices", a.index(), a.count()));
    }
    accessor::floats(&a, buffers)
}

/// The morph-target attributes read (`TANGENT` is not: shading builds its own tangent frame).
#[derive(Clone, Copy, Debug)]
enum Target {
    Position,
    Normal,
}

/// Add to `values` (a VEC3 attribute of `p`, three components a vertex) each morph target's
/// displacement of it times the target's weight (glTF 2.0 §3.7.2.2: the default pose is the base
/// plus Σ wᵢ·targetᵢ); targets under weight 0 are not read.
fn morph(
    p: &gltf::Primitive,
    buffers: &[Rc<Vec<u8>>],
    weights: &[f32],
    target: Target,
    values: &mut [f32],
) -> Result<(), String> {
    for (i, (t, &w)) in p.morph_targets().zip(weights).enumerate() {
        let accessor = match target {
            Target::Position => t.positions(),
            Target::Normal => t.normals(),
        };
        let Some(a) = accessor.filter(|_| w != 0.0) else { continue };
        let name = format!("morph target {i} {target:?} accessor {}", a.index());
        if a.dimensions() != Dimensions::Vec3 || a.count() != values.len() / 3 {
            return Err(format!("{name}: must be VEC3 with one element per vertex ({})", values.len() / 3));
        }
        for (v, d) in values.iter_mut().zip(accessor::floats(&a, buffers)?) {
            *v += w * d;
        }
    }
    Ok(())
}
