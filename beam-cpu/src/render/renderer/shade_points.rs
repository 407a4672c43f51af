//! Shade points of the eye beams' fragments: a pixel's fragments that see one smooth stretch of
//! surface (the same material, normals within [`SMOOTH`], depths within [`CONTINUOUS`]) are shaded
//! once, at the largest of them, with their coverage summed. On a finely tessellated mesh a pixel
//! holds a fragment per visible triangle, and each shaded on its own would cost a shadow beam per
//! light apiece for differences below the flat shading of neighbouring facets; silhouettes, creases
//! and material boundaries keep their fragments apart, so their coverage stays exact.

use super::context::Surface;
use crate::render::eye_regions::{Region, TILE};
use beam_math::glam::Vec3;
use beam_scene::scene::Scene;

/// Cosine of the largest angle between the normals of fragments shaded as one.
const SMOOTH: f32 = 0.906; // 25°

/// Largest relative difference of the distances along the view of fragments shaded as one.
const CONTINUOUS: f32 = 0.05;

/// Order the fragments of `window`'s pixels as they are shaded: tile by tile of the frame's grid
/// (rows of tiles, each left to right), row by row within a tile, each pixel's largest coverage
/// first. Stable, and linear in the fragments: a counting sort on the pixel's place in that order,
/// then each pixel's few fragments by coverage.
pub(super) fn sort_by_tile(surfaces: &mut Vec<Surface>, window: Region) {
    if surfaces.is_empty() {
        return;
    }
    let (tx0, ty0) = (window.x0 / TILE, window.y0 / TILE);
    let columns = (window.x1.div_ceil(TILE) - tx0) as usize;
    let rows = (window.y1.div_ceil(TILE) - ty0) as usize;
    let place = |s: &Surface| {
        debug_assert!((window.x0..window.x1).contains(&s.x) && (window.y0..window.y1).contains(&s.y));
        let tile = (s.y / TILE - ty0) as usize * columns + (s.x / TILE - tx0) as usize;
        (tile * TILE as usize + (s.y % TILE) as usize) * TILE as usize + (s.x % TILE) as usize
    };
    let mut start = vec![0usize; rows * columns * (TILE * TILE) as usize + 1];
    for s in surfaces.iter() {
        start[place(s) + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut sorted = surfaces.clone();
    for s in surfaces.iter() {
        let at = &mut start[place(s)];
        sorted[*at] = *s;
        *at += 1;
    }
    for pixel in sorted.chunk_by_mut(|a, b| (a.x, a.y) == (b.x, b.y)) {
        pixel.sort_by(|a, b| b.weight.total_cmp(&a.weight));
    }
    *surfaces = sorted;
}

/// Merge each pixel's fragments that see one smooth stretch of surface into the largest of them
/// (its coverage the sum of theirs). `surfaces` come as [`sort_by_tile`] leaves them, and stay so.
pub(super) fn merge_smooth(scene: &Scene, camera: Vec3, surfaces: &mut Vec<Surface>) {
    let mut kept = 0;
    let mut start = 0;
    // The stretches of the pixel's kept fragments, `first_kept..kept`.
    let mut stretches: Vec<Stretch> = Vec::new();
    while start < surfaces.len() {
        let end = start
            + surfaces[start..].iter().take_while(|s| (s.x, s.y) == (surfaces[start].x, surfaces[start].y)).count();
        let first_kept = kept;
        stretches.clear();
        for i in start..end {
            let s = surfaces[i];
            let stretch = Stretch::of(scene, camera, &s);
            match stretches.iter().position(|o| o.joins(&stretch)) {
                Some(k) => surfaces[first_kept + k].weight += s.weight,
                None => {
                    surfaces[kept] = s;
                    kept += 1;
                    stretches.push(stretch);
                }
            }
        }
        start = end;
    }
    surfaces.truncate(kept);
}

/// What decides whether two fragments see one smooth stretch of surface: the material, the
/// geometric normal turned to face the viewer, the distance from the camera.
#[derive(Clone, Copy, Debug)]
pub(super) struct Stretch {
    material: u32,
    normal: Vec3,
    distance: f32,
}

impl Stretch {
    /// The stretch fragment `s` sees from `camera`.
    pub(super) fn of(scene: &Scene, camera: Vec3, s: &Surface) -> Self {
        let material = scene.material_of[s.prim as usize];
        Self { material, normal: facing_normal(scene, s), distance: (s.q - camera).length() }
    }

    /// Whether `self` and `s` are one smooth stretch: the same material, normals within
    /// [`SMOOTH`], distances within [`CONTINUOUS`] of `s`'s.
    pub(super) fn joins(&self, s: &Self) -> bool {
        self.material == s.material
            && self.normal.dot(s.normal) >= SMOOTH
            && (self.distance - s.distance).abs() <= CONTINUOUS * s.distance
    }
}

/// The fragment's geometric normal, turned to face the viewer.
fn facing_normal(scene: &Scene, s: &Surface) -> Vec3 {
    let n = scene.normal(s.prim);
    if n.dot(s.d) > 0.0 { -n } else { n }
}
