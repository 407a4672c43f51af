//! Shade points of the eye beams' fragments: a pixel's fragments that see one smooth stretch of
//! surface (the same material, normals within [`SMOOTH`], depths within [`CONTINUOUS`]) are shaded
//! once, at the largest of them, with their coverage summed. On a finely tessellated mesh a pixel
//! holds a fragment per visible triangle, and each shaded on its own would cost a shadow beam per
//! light apiece for differences below the flat shading of neighbouring facets; silhouettes, creases
//! and material boundaries keep their fragments apart, so their coverage stays exact.

use super::context::Surface;
use beam_scene::scene::Scene;

/// Cosine of the largest angle between the normals of fragments shaded as one.
const SMOOTH: f32 = 0.906; // 25°

/// Largest relative difference of the distances along the view of fragments shaded as one.
const CONTINUOUS: f32 = 0.05;

/// Merge each pixel's fragments that see one smooth stretch of surface into the largest of them
/// (its coverage the sum of theirs). `surfaces` is left sorted by pixel, row by row.
pub(super) fn merge_smooth(scene: &Scene, camera: beam_math::glam::Vec3, surfaces: &mut Vec<Surface>) {
    // By pixel, largest coverage first.
    surfaces.sort_by(|a, b| (a.y, a.x).cmp(&(b.y, b.x)).then(b.weight.total_cmp(&a.weight)));
    let mut kept = 0;
    let mut start = 0;
    while start < surfaces.len() {
        let end = start
            + surfaces[start..].iter().take_while(|s| (s.x, s.y) == (surfaces[start].x, surfaces[start].y)).count();
        let first_kept = kept;
        for i in start..end {
            let s = surfaces[i];
            let n = facing_normal(scene, &s);
            let t = (s.q - camera).length();
            let joined = (first_kept..kept).find(|&k| {
                let o = &surfaces[k];
                scene.material_of[o.prim as usize] == scene.material_of[s.prim as usize]
                    && facing_normal(scene, o).dot(n) >= SMOOTH
                    && ((o.q - camera).length() - t).abs() <= CONTINUOUS * t
            });
            match joined {
                Some(k) => surfaces[k].weight += s.weight,
                None => {
                    surfaces[kept] = s;
                    kept += 1;
                }
            }
        }
        start = end;
    }
    surfaces.truncate(kept);
}

/// The fragment's geometric normal, turned to face the viewer.
fn facing_normal(scene: &Scene, s: &Surface) -> beam_math::glam::Vec3 {
    let n = scene.normal(s.prim);
    if n.dot(s.d) > 0.0 { -n } else { n }
}
