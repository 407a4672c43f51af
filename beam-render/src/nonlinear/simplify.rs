//! Coarse S meshes by simplification (000 §7.1: "we build its S mesh via mesh simplification"):
//! the specular triangles are welded into surfaces (one material, vertices joined where position
//! and smooth normal agree, so that creases stay as borders), split into connected surfaces, and
//! each is simplified by meshoptimizer's edge-collapse simplifier (`meshopt::simplify`, quadric
//! error metric) to its share of a face count, or within an error.

use super::coarse::Group;
use beam_math::glam::Vec3;
use beam_scene::scene::{Scene, Simplify};
use meshopt::SimplifyOptions;
use std::collections::HashMap;

/// Corners closer than this fraction of the surfaces' size weld (as the smooth normals do).
const WELD: f32 = 1e-5;

/// Corners whose smooth normals are closer than this (cosine) weld; others stay apart (a crease).
const SAME_NORMAL: f32 = 0.99;

/// Weight of the smooth normals (unit vectors) in the simplifier's error beside the positions
/// (relative to the mesh's size): the beams' directions follow the normals, so the faces go where
/// the surfaces turn. On the mirror teapot at 1,000 faces the rms error of S1 directions against
/// the reflections about the fine normals is 10.2° with positions alone, 5.8° at weight 0.5 and
/// 4.2° at 8; at 850 faces the rendered image (without caustics, before folded faces were traced
/// by rays) was 32.8 dB from the reference at 16 and 32.0 at 32.
const NORMAL_WEIGHT: f32 = 16.0;

/// Fewest faces a simplified surface keeps.
const MIN_FACES: usize = 4;

/// The specular triangles `prims` of `scene` as connected surfaces of one material with their S
/// meshes: all of them simplified together to `target` (so that the faces go where the surfaces
/// curve most), the smooth normals weighing in the simplifier's error beside the positions (the
/// normals are what the beams' directions follow), then split into the surfaces again.
#[must_use]
pub(super) fn simplified(scene: &Scene, prims: &[u32], target: Simplify) -> Vec<Group> {
    let surfaces = surfaces(scene, prims);
    // One mesh of every surface: offsets of each surface's vertices.
    let mut first = Vec::with_capacity(surfaces.len());
    let (mut flat, mut positions, mut attributes) = (Vec::new(), Vec::new(), Vec::new());
    for s in &surfaces {
        let base = positions.len() as u32;
        first.push(base);
        flat.extend(s.triangles.iter().flatten().map(|&i| base + i));
        positions.extend(s.positions.iter().map(|p| p.to_array()));
        attributes.extend(s.normals.iter().flat_map(|n| n.to_array()));
    }
    let faces = flat.len() / 3;
    let (count, error) = match target {
        Simplify::Faces(n) => (n as usize, f32::MAX),
        Simplify::Error(e) => (MIN_FACES, e),
    };
    let out = if count >= faces {
        flat.clone()
    } else {
        let locks = vec![false; positions.len()];
        meshopt::simplify_with_attributes_and_locks_decoder(
            &flat,
            &positions,
            &attributes,
            &[NORMAL_WEIGHT; 3],
            12,
            &locks,
            3 * count.max(MIN_FACES),
            error,
            SimplifyOptions::None,
            None,
        )
    };
    // Back to the surfaces: each kept triangle by the surface of its first vertex.
    let mut kept: Vec<Vec<[u32; 3]>> = vec![Vec::new(); surfaces.len()];
    for t in out.chunks_exact(3) {
        let k = first.partition_point(|&f| f <= t[0]) - 1;
        kept[k].push([t[0], t[1], t[2]].map(|i| i - first[k]));
    }
    surfaces
        .into_iter()
        .zip(kept)
        .map(|(s, kept)| {
            // A surface simplified away entirely keeps its own triangles.
            let indices = if kept.is_empty() { s.triangles } else { kept };
            Group { prims: s.prims, positions: s.positions, normals: Some(s.normals), indices }
        })
        .collect()
}

/// A welded corner: its material and its position on a lattice of the weld tolerance.
type WeldKey = (u32, (i64, i64, i64));

/// A welded, connected specular surface of one material.
struct Surface {
    /// Its scene triangles (ascending).
    prims: Vec<u32>,
    positions: Vec<Vec3>,
    /// Unit smooth normal per vertex.
    normals: Vec<Vec3>,
    /// Its non-degenerate welded triangles.
    triangles: Vec<[u32; 3]>,
}

/// `prims` welded and split into connected surfaces of one material.
fn surfaces(scene: &Scene, prims: &[u32]) -> Vec<Surface> {
    let (lo, hi) = prims
        .iter()
        .flat_map(|&p| scene.triangles[p as usize].v)
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let tol = WELD * (hi - lo).max_element().max(f32::MIN_POSITIVE);
    let key = |p: Vec3| ((p.x / tol).round() as i64, (p.y / tol).round() as i64, (p.z / tol).round() as i64);
    // Welded vertices: by material and position, then by normal.
    let mut at: HashMap<WeldKey, Vec<u32>> = HashMap::new();
    let (mut positions, mut normals): (Vec<Vec3>, Vec<Vec3>) = (Vec::new(), Vec::new());
    let mut corners: Vec<[u32; 3]> = Vec::with_capacity(prims.len());
    for &p in prims {
        let tri = scene.triangles[p as usize];
        let smooth = scene.smooth_normals.get(&p).copied().unwrap_or([scene.normal(p); 3]);
        let material = scene.material_of[p as usize];
        corners.push([0, 1, 2].map(|k| {
            let ids = at.entry((material, key(tri.v[k]))).or_default();
            if let Some(&id) = ids.iter().find(|&&id| normals[id as usize].dot(smooth[k]) > SAME_NORMAL) {
                return id;
            }
            let id = positions.len() as u32;
            positions.push(tri.v[k]);
            normals.push(smooth[k]);
            ids.push(id);
            id
        }));
    }
    // Connected surfaces: union-find over the welded vertices.
    let mut parent: Vec<u32> = (0..positions.len() as u32).collect();
    let find = |parent: &mut Vec<u32>, mut i: u32| {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    };
    for c in &corners {
        let (a, b, d) = (find(&mut parent, c[0]), find(&mut parent, c[1]), find(&mut parent, c[2]));
        parent[b as usize] = a;
        parent[d as usize] = a;
    }
    let mut index: HashMap<u32, usize> = HashMap::new();
    let mut out: Vec<(Surface, HashMap<u32, u32>)> = Vec::new();
    for (&p, c) in prims.iter().zip(&corners) {
        let root = find(&mut parent, c[0]);
        let k = *index.entry(root).or_insert_with(|| {
            let s = Surface { prims: Vec::new(), positions: Vec::new(), normals: Vec::new(), triangles: Vec::new() };
            out.push((s, HashMap::new()));
            out.len() - 1
        });
        let (s, local) = &mut out[k];
        s.prims.push(p);
        if c[0] == c[1] || c[1] == c[2] || c[2] == c[0] {
            continue; // welded to a sliver: mapped to the S mesh, but no face of it
        }
        let t = c.map(|v| {
            *local.entry(v).or_insert_with(|| {
                s.positions.push(positions[v as usize]);
                s.normals.push(normals[v as usize]);
                s.positions.len() as u32 - 1
            })
        });
        s.triangles.push(t);
    }
    out.into_iter().map(|(s, _)| s).filter(|s| !s.triangles.is_empty()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_scene::scene::Material;

    #[test]
    fn teapot_surfaces_simplify_to_their_share() {
        let scene = beam_scene::scene::showcase::mirror_teapot(12, 8);
        let mirror: Vec<u32> = (0..scene.triangles.len() as u32)
            .filter(|&p| matches!(scene.material(p), Material::Mirror { .. }))
            .collect();
        let s = surfaces(&scene, &mirror);
        // Body, lid (apart where the rim's normals differ), handle and spout.
        assert!((3..=5).contains(&s.len()), "{} surfaces", s.len());
        assert_eq!(s.iter().map(|s| s.prims.len()).sum::<usize>(), mirror.len());
        let groups = simplified(&scene, &mirror, Simplify::Faces(200));
        let faces: usize = groups.iter().map(|g| g.indices.len()).sum();
        assert!((150..=260).contains(&faces), "{faces} faces");
        for g in &groups {
            // The simplifier keeps a subset of the welded vertices, so their normals stay the fine ones.
            assert!(g.indices.iter().flatten().all(|&i| (i as usize) < g.positions.len()));
            assert!(g.normals.as_ref().unwrap().iter().all(|n| (n.length() - 1.0).abs() < 1e-3));
        }
        // A tiny error keeps most faces (only flat parts, such as the bottom, collapse).
        let all: usize = s.iter().map(|s| s.triangles.len()).sum();
        let kept: usize = simplified(&scene, &mirror, Simplify::Error(1e-6)).iter().map(|g| g.indices.len()).sum();
        assert!(kept <= all && kept > all / 2, "{kept} of {all}");
    }
}
