//! Smooth vertex normals of the specular (mirror and glass) triangles: the curved surfaces that the
//! S mesh of 000 §7.1 stands for, shared by the nonlinear beams and the ray-traced reference.

use super::material::Material;
use beam_math::Triangle;
use beam_math::glam::Vec3;
use rustc_hash::FxHashMap;
use std::collections::HashMap;

/// Per specular triangle, its three unit vertex normals on the side of its geometric normal: the
/// normals of the triangles of the same material that share the vertex's position (welded to 1e-5 of
/// the scene's size) and lie within 60° of the triangle (so that creases, such as a lens's rim, stay
/// sharp), summed with Max's weights `(e1 × e2)/(|e1|²|e2|²)` (N. Max, *Weights for computing vertex
/// normals from facet normals*, 1999), which give the exact normal when the vertex and its
/// neighbours lie on a sphere.
#[must_use]
pub(super) fn specular_normals(
    triangles: &[Triangle],
    material_of: &[u32],
    materials: &[Material],
) -> FxHashMap<u32, [Vec3; 3]> {
    let specular =
        |p: usize| matches!(materials[material_of[p] as usize], Material::Mirror { .. } | Material::Glass { .. });
    let prims: Vec<usize> = (0..triangles.len()).filter(|&p| specular(p)).collect();
    let extent = prims
        .iter()
        .flat_map(|&p| triangles[p].v)
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let tol = 1e-5 * (extent.1 - extent.0).max_element().max(f32::MIN_POSITIVE);
    let key = |p: Vec3| ((p.x / tol).round() as i64, (p.y / tol).round() as i64, (p.z / tol).round() as i64);
    // Slivers whose corners weld together (a sphere's pole) have no trustworthy normal of their own:
    // they take their neighbours' normals and lend none.
    let sliver = |p: usize| {
        let k = triangles[p].v.map(key);
        k[0] == k[1] || k[1] == k[2] || k[2] == k[0]
    };
    let mut at: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for &p in prims.iter().filter(|&&p| !sliver(p)) {
        for v in triangles[p].v {
            at.entry(key(v)).or_default().push(p);
        }
    }
    prims
        .iter()
        .map(|&p| {
            let own = triangles[p].scaled_normal().normalize_or_zero();
            let near = if sliver(p) { -1.0 } else { 0.5 };
            let n = triangles[p].v.map(|v| {
                let sum: Vec3 = at
                    .get(&key(v))
                    .into_iter()
                    .flatten()
                    .filter(|&&q| material_of[q] == material_of[p])
                    .filter(|&&q| triangles[q].scaled_normal().normalize_or_zero().dot(own) > near)
                    .filter_map(|&q| {
                        let t = triangles[q].v;
                        let i = (0..3).find(|&i| key(t[i]) == key(v))?;
                        let (e1, e2) = (t[(i + 1) % 3] - t[i], t[(i + 2) % 3] - t[i]);
                        let w = e1.length_squared() * e2.length_squared();
                        (w > tol.powi(4)).then(|| e1.cross(e2) / w)
                    })
                    .sum();
                sum.try_normalize().map_or(own, |n| if n.dot(own) < 0.0 { -n } else { n })
            });
            (p as u32, n)
        })
        .collect()
}
