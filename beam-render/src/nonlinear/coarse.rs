//! A coarse S mesh over a group of fine specular triangles (000 §7.1: beams spawn from the coarse
//! S mesh, the fine mesh is rendered and textured from them): its faces with the fine mesh's smooth
//! normals at their vertices, each fine triangle's candidate faces (those its points lie nearest),
//! and per face the fine triangles its beams must not hit (its patch) or may hit only beyond the
//! self-hit distance (its ring: the patches of the faces that share a vertex with it).

use super::face::{SFace, sliver_face};
use super::nearest::Nearest;
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_scene::scene::Scene;
use rayon::prelude::*;
use std::collections::HashMap;

/// Fine specular triangles and the coarse mesh over them.
pub(super) struct Group {
    /// The scene triangles (ascending).
    pub prims: Vec<u32>,
    /// Coarse vertices.
    pub positions: Vec<Vec3>,
    /// Unit smooth normals at the coarse vertices when known (a simplified mesh keeps fine
    /// vertices); else found on the fine mesh.
    pub normals: Option<Vec<Vec3>>,
    /// Coarse triangles.
    pub indices: Vec<[u32; 3]>,
}

/// The usable faces of a group's coarse mesh and the map of its fine triangles onto them, which the
/// S mesh appends ([`SMesh`](super::SMesh)).
pub(super) struct CoarseFaces {
    /// Per fine triangle of the group (in the order of [`Group::prims`]): its candidate faces,
    /// ascending indices into `faces`.
    pub candidates: Vec<Vec<u32>>,
    /// The faces.
    pub faces: Vec<CoarseFace>,
}

/// One face of a coarse S mesh with what its beams skip.
pub(super) struct CoarseFace {
    /// The face.
    pub face: SFace,
    /// The fine triangles under it (its patch), ascending.
    pub patch: Vec<u32>,
    /// The fine triangles under the faces sharing a vertex with it, outside its patch, ascending.
    pub ring: Vec<u32>,
    /// The thickness of the fine surface about the face's plane, over its patch.
    pub thickness: f32,
}

/// The faces of `g`'s coarse mesh and the map of `g`'s triangles onto them; `None` when the coarse
/// mesh has no usable face.
pub(super) fn coarse_faces(scene: &Scene, g: &Group) -> Option<CoarseFaces> {
    let fine: Vec<Triangle> = g.prims.iter().map(|&p| scene.triangles[p as usize]).collect();
    let near_fine = Nearest::new(&fine);
    // The fine mesh's smooth normal at (or nearest to) a point: Phong over its nearest triangle.
    let smooth_at = |q: Vec3| -> Option<(u32, Vec3)> {
        let (i, c) = near_fine.query(q)?;
        let prim = g.prims[i as usize];
        let n = match (scene.smooth_normals.get(&prim), fine[i as usize].barycentric(c)) {
            (Some(n), Some(w)) => (w.x * n[0] + w.y * n[1] + w.z * n[2]).try_normalize(),
            _ => None,
        };
        Some((prim, n.unwrap_or_else(|| scene.normal(prim))))
    };
    let normals: Vec<Vec3> = match &g.normals {
        Some(n) => n.clone(),
        None => g.positions.par_iter().map(|&q| smooth_at(q).map_or(Vec3::ZERO, |(_, n)| n)).collect(),
    };
    // Faces, oriented so that their normals lie on the vertex normals' side.
    let mut faces: Vec<SFace> = Vec::new();
    for idx in &g.indices {
        let Some(v) = idx.iter().map(|&i| g.positions.get(i as usize).copied()).collect::<Option<Vec<_>>>() else {
            continue;
        };
        let (mut v, mut n) = ([v[0], v[1], v[2]], idx.map(|i| normals[i as usize]));
        let tri = Triangle { v };
        // Slivers (a pole's) make no beam worth having; their points map to their neighbours.
        if !tri.is_valid() || sliver_face(&v) || n.iter().any(|n| !n.is_finite() || *n == Vec3::ZERO) {
            continue;
        }
        let mut normal = tri.scaled_normal().normalize_or_zero();
        if normal.dot(n[0] + n[1] + n[2]) < 0.0 {
            v.swap(1, 2);
            n.swap(1, 2);
            normal = -normal;
        }
        let centre = (v[0] + v[1] + v[2]) / 3.0;
        let Some((prim, _)) = smooth_at(centre) else { continue };
        faces.push(SFace { prim, v, n, normal });
    }
    if faces.is_empty() {
        return None;
    }
    let coarse: Vec<Triangle> = faces.iter().map(|f| Triangle { v: f.v }).collect();
    let near_coarse = Nearest::new(&coarse);
    // Each fine triangle's candidates: the faces nearest its corners, edge midpoints and centre that
    // face its way (any face when none does).
    let candidates: Vec<Vec<u32>> = fine
        .par_iter()
        .map(|t| {
            let [a, b, c] = t.v;
            // Among the faces on the triangle's side: not the far side of a thin part (a handle).
            let facing = t.scaled_normal();
            let mut out: Vec<u32> = [a, b, c, (a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0, (a + b + c) / 3.0]
                .into_iter()
                .filter_map(|q| near_coarse.query_facing(q, facing).or_else(|| near_coarse.query(q)).map(|(i, _)| i))
                .collect();
            out.sort_unstable();
            out.dedup();
            out
        })
        .collect();
    // Patches (sorted, since the prims are), then rings through the coarse vertices' positions.
    let mut patch: Vec<Vec<u32>> = vec![Vec::new(); faces.len()];
    for (&p, c) in g.prims.iter().zip(&candidates) {
        for &f in c {
            patch[f as usize].push(p);
        }
    }
    let mut at: HashMap<[u32; 3], Vec<u32>> = HashMap::new();
    for (k, f) in faces.iter().enumerate() {
        for v in f.v {
            at.entry(v.to_array().map(f32::to_bits)).or_default().push(k as u32);
        }
    }
    let mut coarse_faces = Vec::with_capacity(faces.len());
    for (k, f) in faces.iter().enumerate() {
        let mut ring: Vec<u32> =
            f.v.iter()
                .flat_map(|v| &at[&v.to_array().map(f32::to_bits)])
                .filter(|&&j| j as usize != k)
                .flat_map(|&j| patch[j as usize].iter().copied())
                .filter(|p| patch[k].binary_search(p).is_err())
                .collect();
        ring.sort_unstable();
        ring.dedup();
        // The thickness of the fine surface about the face's plane, over its patch.
        let thickness = patch[k]
            .iter()
            .flat_map(|&p| scene.triangles[p as usize].v)
            .fold(0.0f32, |m, v| m.max((v - f.v[0]).dot(f.normal).abs()));
        // A clone: the faces after it read this patch for their rings.
        coarse_faces.push(CoarseFace { face: *f, patch: patch[k].clone(), ring, thickness });
    }
    Some(CoarseFaces { candidates, faces: coarse_faces })
}
