//! Shade points of the eye beams' fragments: a pixel's fragments that see one smooth stretch of
//! surface (the same material, normals within [`SMOOTH`], depths within [`CONTINUOUS`]) are shaded
//! once, at the largest of them, with their coverage summed. On a finely tessellated mesh a pixel
//! holds a fragment per visible triangle, and each shaded on its own would cost a shadow beam per
//! light apiece for differences below the flat shading of neighbouring facets; silhouettes, creases
//! and material boundaries keep their fragments apart, so their coverage stays exact. Without
//! `--exact`, a sliver of an edge pixel is shaded at a neighbouring pixel's point of its stretch
//! ([`lend_slivers`]).

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
fn sort_by_tile(surfaces: &mut Vec<Surface>, window: Region) {
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

/// Turn a region's fragments in `window` into its shade points: ordered by tile
/// ([`sort_by_tile`]), each pixel's fragments on one stretch merged ([`merge_smooth`]), and where
/// `lend`, slivers shaded at a neighbour's point ([`lend_slivers`], whose count it returns).
pub(super) fn shade_points(
    scene: &Scene,
    camera: Vec3,
    (surfaces, window): (&mut Vec<Surface>, Region),
    lend: bool,
) -> u64 {
    sort_by_tile(surfaces, window);
    let mut stretches = merge_smooth(scene, camera, surfaces);
    if lend { lend_slivers(surfaces, &mut stretches) } else { 0 }
}

/// Merge each pixel's fragments that see one smooth stretch of surface into the largest of them
/// (its coverage the sum of theirs). `surfaces` come as [`sort_by_tile`] leaves them, and stay so.
/// Returns the kept fragments' stretches, one for each.
fn merge_smooth(scene: &Scene, camera: Vec3, surfaces: &mut Vec<Surface>) -> Vec<Stretch> {
    let mut stretches: Vec<Stretch> = Vec::with_capacity(surfaces.len());
    let (mut kept, mut start) = (0, 0);
    while start < surfaces.len() {
        let end = start
            + surfaces[start..].iter().take_while(|s| (s.x, s.y) == (surfaces[start].x, surfaces[start].y)).count();
        let first_kept = kept;
        for i in start..end {
            let s = surfaces[i];
            let stretch = Stretch::of(scene, camera, &s);
            match stretches[first_kept..].iter().position(|o| o.joins(&stretch)) {
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
    stretches
}

/// Largest coverage of a fragment shaded at a neighbour's point ([`lend_slivers`]): one of the
/// 2 × 2 rays of a ray region's edge pixel.
const SLIVER: f32 = 0.25;

/// Shade the slivers of edge pixels at their neighbours' points: in a pixel that holds more than
/// one shade point (an edge passes through it), a fragment of at most [`SLIVER`] coverage whose
/// stretch of surface is one with a shade point of the pixel to its left or of the one above, in
/// its tile, is dropped and its weight lent to that point ([`Surface::lent`]): shaded one pixel
/// away, as a pixel's fragments on one stretch are all shaded at its largest ([`merge_smooth`]).
/// `surfaces` and their `stretches` come as [`merge_smooth`] leaves them, and stay so. Returns
/// how many were lent.
fn lend_slivers(surfaces: &mut Vec<Surface>, stretches: &mut Vec<Stretch>) -> u64 {
    const SIDE: usize = TILE as usize;
    debug_assert_eq!(surfaces.len(), stretches.len());
    let mut lent = 0;
    // Per pixel of the tile being read, the range of its kept points.
    let mut own = [(0, 0); SIDE * SIDE];
    let (mut kept, mut start, mut tile) = (0, 0, None);
    while start < surfaces.len() {
        let (x, y) = (surfaces[start].x, surfaces[start].y);
        let end = start + surfaces[start..].iter().take_while(|s| (s.x, s.y) == (x, y)).count();
        if tile != Some((x / TILE, y / TILE)) {
            (tile, own) = (Some((x / TILE, y / TILE)), [(0, 0); SIDE * SIDE]);
        }
        let (tx, ty) = ((x % TILE) as usize, (y % TILE) as usize);
        let left = if tx > 0 { own[ty * SIDE + tx - 1] } else { (0, 0) };
        let above = if ty > 0 { own[(ty - 1) * SIDE + tx] } else { (0, 0) };
        let mine = kept;
        for i in start..end {
            let (s, stretch) = (surfaces[i], stretches[i]);
            let joins = |(a, b): (usize, usize)| (a..b).find(|&k| stretches[k].joins(&stretch));
            let lender = if end - start > 1 && s.weight <= SLIVER {
                joins(left).map(|k| (k, 0)).or_else(|| joins(above).map(|k| (k, 1)))
            } else {
                None
            };
            if let Some((k, side)) = lender {
                surfaces[k].lent[side] += s.weight;
                lent += 1;
            } else {
                (surfaces[kept], stretches[kept]) = (s, stretch);
                kept += 1;
            }
        }
        own[ty * SIDE + tx] = (mine, kept);
        start = end;
    }
    surfaces.truncate(kept);
    stretches.truncate(kept);
    lent
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

#[cfg(test)]
mod tests {
    use super::*;
    use beam_math::Triangle;
    use beam_scene::scene::{Camera, Material};

    /// A floor (triangle 0, material 0) and a wall (triangle 1, material 1) seen from above.
    fn floor_and_wall() -> Scene {
        let floor = Triangle::new(Vec3::new(-5.0, 0.0, -5.0), Vec3::new(5.0, 0.0, -5.0), Vec3::new(0.0, 0.0, 5.0));
        let wall = Triangle::new(Vec3::new(-5.0, 0.0, -1.0), Vec3::new(5.0, 0.0, -1.0), Vec3::new(0.0, 5.0, -1.0));
        let plain = Material::Diffuse { albedo: Vec3::splat(0.5) };
        let camera = Camera {
            position: Vec3::new(0.0, 10.0, 0.0),
            target: Vec3::ZERO,
            up: Vec3::Z,
            fov_y: 40.0,
            width: 32,
            height: 32,
        };
        Scene::new("floor and wall".into(), vec![(floor, 0), (wall, 1)], vec![plain, plain], Vec::new(), camera)
    }

    fn fragment((x, y): (u32, u32), weight: f32, prim: u32) -> Surface {
        let q = if prim == 0 { Vec3::new(0.1, 0.0, 0.0) } else { Vec3::new(0.1, 1.0, -1.0) };
        let d = (q - Vec3::new(0.0, 10.0, 0.0)).normalize();
        Surface { x, y, weight, prim, q, d, seed: 0, lent: [0.0; 2] }
    }

    /// A sliver of an edge pixel goes to the point of its stretch in the pixel to its left or the
    /// one above, in its tile; larger fragments, lone fragments and other tiles' points stay.
    #[test]
    fn slivers_go_to_the_left_or_upper_neighbours_point() {
        let scene = floor_and_wall();
        let camera = scene.camera.position;
        let mut surfaces = vec![
            fragment((0, 0), 1.0, 1),
            fragment((1, 0), 0.75, 0),
            fragment((1, 0), 0.25, 1),
            fragment((2, 0), 0.5, 0),
            fragment((2, 0), 0.5, 1),
            fragment((15, 0), 1.0, 1),
            fragment((0, 1), 0.75, 0),
            fragment((0, 1), 0.25, 1),
            fragment((1, 1), 0.25, 1),
            // The next tile: its left neighbour (15, 0) lies in another.
            fragment((16, 0), 0.75, 0),
            fragment((16, 0), 0.25, 1),
        ];
        let mut stretches = surfaces.iter().map(|s| Stretch::of(&scene, camera, s)).collect();
        let lent = lend_slivers(&mut surfaces, &mut stretches);
        assert_eq!(lent, 2);
        let at =
            |x, y| surfaces.iter().filter(|s| (s.x, s.y) == (x, y)).map(|s| (s.prim, s.weight)).collect::<Vec<_>>();
        assert_eq!(surfaces[0].lent, [0.25, 0.25], "(1, 0)'s and (0, 1)'s wall slivers");
        assert_eq!(at(1, 0), [(0, 0.75)]);
        assert_eq!(at(0, 1), [(0, 0.75)]);
        assert_eq!(at(2, 0), [(0, 0.5), (1, 0.5)], "no sliver");
        assert_eq!(at(1, 1), [(1, 0.25)], "a lone fragment");
        assert_eq!(at(16, 0), [(0, 0.75), (1, 0.25)], "across a tile's edge");
        let targets: Vec<_> = surfaces[0].targets().collect();
        assert_eq!(targets, [((0, 0), 1.0), ((1, 0), 0.25), ((0, 1), 0.25)]);
        // What was lent and what stayed still cover each pixel as before.
        let weight = |x, y| {
            surfaces.iter().flat_map(Surface::targets).filter(|&(p, _)| p == (x, y)).map(|(_, w)| w).sum::<f32>()
        };
        for (x, y) in [(0, 0), (1, 0), (2, 0), (0, 1), (16, 0)] {
            assert_eq!(weight(x, y), 1.0, "({x}, {y})");
        }
    }
}
