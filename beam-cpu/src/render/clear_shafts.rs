//! Shade points that see a whole light, found a tile at a time where shadow beams do not pay
//! (fewer rays a light than a beam's set-up costs, as under many small lights): the shaft from a
//! block of the tile's points to the light ([`super::shaft`]) meets no triangle, so each of those
//! points gets the light's unoccluded irradiance exactly (001 eq. 1) instead of its shadow rays.
//! One test stops at the first triangle it meets; the whole tile is tried first, then its blocks,
//! and only where the rays a test could save pay for it; under many small emitters, one test
//! serves a group of neighbouring emitters ([`super::light_groups`]).

use super::light_groups::{LightGroup, group_lights};
use super::shaft::{Shaft, meets_any};
use super::tile_shadows::BLOCKS;
use beam_math::Aabb;
use beam_math::glam::Vec3;
use beam_scene::scene::{Light, Scene};

/// What one shaft test costs, in shadow rays (about 50 BVH nodes at 75 ns against a ray's 90 ns,
/// spheres-256 on this machine).
const SHAFT_RAYS: u32 = 45;

/// What a point's exact irradiance from a light costs, in shadow rays (Lambert's formula in double
/// precision over a triangle: 0.24 µs). Below one more ray than this, a clear shaft saves nothing.
pub(crate) const LAMBERT_RAYS: u32 = 3;

/// Shadow rays' worth of work a clear shaft saves each of its points that would trace `rays`:
/// past [`LAMBERT_RAYS`], all but the exact irradiance's cost; below, a little (its samples are
/// still drawn and weighed, only not traced, and a ray through empty space is a cheap one).
fn saved_rays(rays: u32) -> f32 {
    if rays > LAMBERT_RAYS { (rays - LAMBERT_RAYS) as f32 } else { 0.25 * rays as f32 }
}

/// Whether testing the shaft of `points` points that would each save `saved` rays' worth of
/// work if it is clear pays: what it saves is worth twice its test.
fn pays(points: usize, saved: f32) -> bool {
    points as f32 * saved >= (2 * SHAFT_RAYS) as f32
}

/// Per light and block of a tile, the box of the block's points that see the whole light.
#[derive(Default)]
pub(crate) struct ClearShafts {
    /// `clear[light · BLOCKS² + block]`: the block's box if a shaft that holds it met no triangle,
    /// else empty.
    clear: Vec<Aabb>,
    /// Per block, its points' box and count for the light being tested.
    boxes: Vec<(Aabb, u32)>,
    /// Shafts tested.
    pub(crate) shafts: u64,
    /// BVH nodes the tests visited.
    pub(crate) bvh_steps: u64,
    /// The lights' groups ([`group_lights`]), made on the first tile that needs them.
    groups: Option<Vec<LightGroup>>,
    /// Per light, whether it faces the tile.
    facing: Vec<bool>,
}

impl ClearShafts {
    /// Test the shafts from the points `points` (each with its block index, `< BLOCKS²`) to each
    /// area light of `lights` listed in `facing` below index `walk_from` (a constant environment's
    /// faces from there on enclose the scene: their shafts would meet it all), where a shade point
    /// would trace `rays` shadow rays to it: the tile's first, then, where one meets a triangle,
    /// its quarters' in turn, as long as the rays a clear shaft would save are worth twice its
    /// test. Where one light's rays are too few for that, the shafts go to groups of neighbouring
    /// lights on one plane instead ([`group_lights`]), each saving the rays to all its lights.
    pub(crate) fn build(
        &mut self,
        scene: &Scene,
        (lights, walk_from): (&[Light], usize),
        facing: &[u32],
        points: &[(usize, Vec3)],
        rays: u32,
    ) {
        self.clear.clear();
        if pays(points.len(), saved_rays(rays)) {
            self.clear.resize(lights.len() * BLOCKS * BLOCKS, Aabb::EMPTY);
            for &index in facing.iter().filter(|&&i| (i as usize) < walk_from) {
                let light = &lights[index as usize];
                if !matches!(light, Light::Point { .. }) {
                    self.test(scene, points, (&light.polygon(), light.normal()), (&[index], saved_rays(rays)));
                }
            }
            return;
        }
        // One light's rays do not pay for a shaft; a group's may.
        let groups =
            self.groups.take().unwrap_or_else(|| group_lights(lights, walk_from, scene.bounds().extent().length()));
        self.facing.clear();
        self.facing.resize(lights.len(), false);
        for &i in facing {
            self.facing[i as usize] = true;
        }
        for g in &groups {
            let members: Vec<u32> = g.members.iter().copied().filter(|&i| self.facing[i as usize]).collect();
            let saved = members.len() as f32 * saved_rays(rays);
            if pays(points.len(), saved) {
                self.clear.resize(lights.len() * BLOCKS * BLOCKS, Aabb::EMPTY);
                self.test(scene, points, (&g.rectangle, g.normal), (&members, saved));
            }
        }
        self.groups = Some(groups);
    }

    /// Test the shafts from `points` to the polygon `area` (corners, normal), which holds the
    /// lights `lights`, each point saving `saved` rays' worth of work where it is clear: the
    /// tile's, then its quarters' in turn ([`Square::test`]); a clear one clears its blocks for
    /// every one of `lights`.
    fn test(
        &mut self,
        scene: &Scene,
        points: &[(usize, Vec3)],
        (polygon, ln): (&[Vec3], Vec3),
        (lights, saved): (&[u32], f32),
    ) {
        let center = polygon.iter().sum::<Vec3>() / polygon.len() as f32;
        self.boxes.clear();
        self.boxes.resize(BLOCKS * BLOCKS, (Aabb::EMPTY, 0));
        for &(block, p) in points.iter().filter(|&&(_, p)| ln.dot(p - center) > 0.0) {
            let (b, n) = &mut self.boxes[block];
            *b = b.grow(p);
            *n += 1;
        }
        let mut square = Square {
            boxes: &self.boxes,
            clear: &mut self.clear,
            lights,
            shafts: &mut self.shafts,
            bvh_steps: &mut self.bvh_steps,
            scene,
            light: (polygon, ln),
            saved,
        };
        square.test(0, 0, BLOCKS);
    }

    /// Whether `p`, a point of block `block`, sees the whole of light `light` (`p` lies in the
    /// box of the block's points, and that box's shaft met no triangle).
    pub(crate) fn sees_whole(&self, light: usize, block: usize, p: Vec3) -> bool {
        self.clear.get(light * BLOCKS * BLOCKS + block).is_some_and(|b| b.min.cmple(p).all() && p.cmple(b.max).all())
    }
}

/// One light's (or group's) tests over squares of a tile's blocks.
struct Square<'a> {
    boxes: &'a [(Aabb, u32)],
    /// [`ClearShafts::clear`].
    clear: &'a mut [Aabb],
    /// The lights a clear shaft clears.
    lights: &'a [u32],
    shafts: &'a mut u64,
    bvh_steps: &'a mut u64,
    scene: &'a Scene,
    light: (&'a [Vec3], Vec3),
    /// Shadow rays' worth of work a clear shaft saves each of its points.
    saved: f32,
}

impl Square<'_> {
    /// Test the square of `side` blocks from block `(x, y)`, then, if its shaft meets a triangle,
    /// its quarters.
    fn test(&mut self, x: usize, y: usize, side: usize) {
        let blocks = || (y..y + side).flat_map(move |by| (x..x + side).map(move |bx| bx + by * BLOCKS));
        let (b, n) = blocks().fold((Aabb::EMPTY, 0u32), |(b, n), i| (b.union(self.boxes[i].0), n + self.boxes[i].1));
        if !b.is_valid() || !pays(n as usize, self.saved) {
            return;
        }
        *self.shafts += 1;
        let (meets, steps) =
            meets_any(&self.scene.bvh, &self.scene.triangles, &Shaft::new(&b, self.light.0, self.light.1));
        *self.bvh_steps += steps;
        if !meets {
            for &light in self.lights {
                for i in blocks() {
                    self.clear[light as usize * BLOCKS * BLOCKS + i] = self.boxes[i].0;
                }
            }
        } else if side > 1 {
            let h = side / 2;
            for (dx, dy) in [(0, 0), (h, 0), (0, h), (h, h)] {
                self.test(x + dx, y + dy, h);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_math::Ray;
    use beam_render::tolerance::DEPTH_EPS;
    use beam_scene::scene::builtin;

    /// A 16 × 16 grid of points at height `y` over the first `fraction` of `b`'s width and depth,
    /// in blocks of 4 × 4 as in a tile, each with its block.
    fn floor_grid(b: &Aabb, y: f32, fraction: f32) -> Vec<(usize, Vec3)> {
        let side = BLOCKS * 4;
        let f = |k: usize| (k as f32 + 0.5) / side as f32 * fraction;
        (0..side * side)
            .map(|i| {
                let (x, z) = (i % side, i / side);
                (x / 4 + z / 4 * BLOCKS, Vec3::new(b.min.x + f(x) * b.extent().x, y, b.min.z + f(z) * b.extent().z))
            })
            .collect()
    }

    /// On the Cornell box's floor, under the light just below the ceiling and beside the two
    /// boxes: every point found to see the whole light does (no ray to the light is blocked), and
    /// the points the boxes shadow are not among them.
    #[test]
    fn a_clear_shaft_means_every_ray_to_the_light_is_free() {
        let scene = builtin("cornell").unwrap();
        let b = scene.bounds();
        let light = scene.lights[0];
        // Over the floor, a hair above it.
        let points = floor_grid(&b, b.min.y + 0.5, 1.0);
        let mut clear = ClearShafts::default();
        clear.build(&scene, (&scene.lights, 1), &[0], &points, 64);
        assert!(clear.shafts > 1, "the tile's shaft meets the boxes, so its quarters are tried");
        let polygon = light.polygon();
        let mut seen = 0;
        for &(block, p) in &points {
            let blocked = (0..256).filter(|&k| {
                let (s, t) = ((k % 16) as f32 / 15.0, (k / 16) as f32 / 15.0);
                let q = polygon[0] + (polygon[1] - polygon[0]) * s + (polygon[3] - polygon[0]) * t;
                scene.wide.any_hit(Ray::new(p, q - p), 1.0 - DEPTH_EPS)
            });
            if clear.sees_whole(0, block, p) {
                seen += 1;
                assert_eq!(blocked.count(), 0, "{p} was found clear");
            }
        }
        assert!(seen > 0 && seen < points.len(), "{seen} of {} points clear", points.len());
    }

    /// Under the suite's 256 small emitters at one ray a light (too few for a shaft of one light),
    /// the shafts go to groups of neighbouring emitters: every point found to see a light whole has
    /// no blocked ray to it, and some points are found so.
    #[test]
    fn a_group_shaft_clears_each_of_its_lights() {
        use beam_scene::scene::suite::{self, Case};
        let Case::Built(scene) = suite::case("spheres-256").unwrap() else { panic!("built in") };
        // Over a corner of the floor beside the spheres.
        let points = floor_grid(&scene.bounds(), 1e-3, 0.3);
        let facing: Vec<u32> = (0..scene.lights.len() as u32).collect();
        let mut clear = ClearShafts::default();
        clear.build(&scene, (&scene.lights, scene.lights.len()), &facing, &points, 1);
        assert!(clear.shafts > 0, "groups of lights pay for shafts");
        let mut seen = 0;
        for (i, light) in scene.lights.iter().enumerate() {
            let v = light.polygon();
            for &(_, p) in points.iter().filter(|&&(block, p)| clear.sees_whole(i, block, p)) {
                seen += 1;
                for k in 0..16 {
                    let (s, t) = ((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0);
                    let (s, t) = if s + t > 1.0 { (1.0 - s, 1.0 - t) } else { (s, t) };
                    let q = v[0] + (v[1] - v[0]) * s + (v[2] - v[0]) * t;
                    assert!(
                        !scene.wide.any_hit(Ray::new(p, q - p), 1.0 - DEPTH_EPS),
                        "{p} was found clear of light {i}"
                    );
                }
            }
        }
        assert!(seen > 0, "no point found clear of any light");
    }
}
