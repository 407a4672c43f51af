//! Neighbouring area lights on one plane, grouped for the clear-shaft test
//! ([`super::clear_shafts`]): a rectangle on their plane that holds all of a group's corners
//! stands for them, so that one shaft from a block of points to it, met by no triangle, clears the
//! block for every light of the group (the shaft to each lies inside it). Under many small
//! emitters one ray a light saves too little for a shaft of its own, but a group's rays pay.

use super::renderer::light_samples::tangents;
use beam_math::glam::{UVec2, Vec2, Vec3};
use beam_scene::scene::Light;
use std::collections::HashMap;

/// Lights a group holds about (the cells of a plane's grid are sized for this many).
const GROUP: usize = 16;

/// Neighbouring lights on one plane and the rectangle on it that holds them.
#[derive(Clone, Debug)]
pub(crate) struct LightGroup {
    /// Indices of its lights.
    pub(crate) members: Vec<u32>,
    /// The rectangle's corners, in order.
    pub(crate) rectangle: [Vec3; 4],
    /// The lights' common normal.
    pub(crate) normal: Vec3,
}

/// The groups of `lights[..end]`: area lights whose normals and planes agree to within rounding
/// (every corner within `1e-6` of the scene's `extent` of the first light's plane) are bucketed by
/// plane, and each plane's lights split by a square grid of cells of about [`GROUP`] lights each;
/// a cell of more than one light is a group. Point lights, lights without area and lone lights
/// are in none.
pub(crate) fn group_lights(lights: &[Light], end: usize, extent: f32) -> Vec<LightGroup> {
    let extent = extent.max(f32::MIN_POSITIVE);
    let tol = 1e-6 * extent;
    // By quantized normal and offset; a plane split across two keys only makes smaller groups.
    let mut planes: HashMap<[i32; 4], Vec<u32>> = HashMap::new();
    for (i, light) in lights[..end].iter().enumerate() {
        let n = light.normal();
        // A point light, or a polygon without area, has no plane.
        if n == Vec3::ZERO {
            continue;
        }
        let c = light.polygon()[0];
        let q = |x: f32| (x * 1e4).round() as i32;
        planes.entry([q(n.x), q(n.y), q(n.z), q(n.dot(c) / extent)]).or_default().push(i as u32);
    }
    let mut groups = Vec::new();
    let mut keys: Vec<_> = planes.keys().copied().collect();
    keys.sort_unstable();
    for key in keys {
        let members = &planes[&key];
        let first = &lights[members[0] as usize];
        let (n, d) = (first.normal(), first.normal().dot(first.polygon()[0]));
        let on_plane: Vec<u32> = members
            .iter()
            .copied()
            .filter(|&i| {
                let l = &lights[i as usize];
                l.normal().distance(n) <= 1e-6 && l.polygon().iter().all(|v| (n.dot(*v) - d).abs() <= tol)
            })
            .collect();
        if on_plane.len() < 2 {
            continue;
        }
        let (u, v) = tangents(n);
        let at = |p: Vec3| Vec2::new(u.dot(p), v.dot(p));
        let centres: Vec<Vec2> = on_plane.iter().map(|&i| at(lights[i as usize].center())).collect();
        let (lo, hi) = centres.iter().fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), &c| (lo.min(c), hi.max(c)));
        let side = ((on_plane.len() as f32 / GROUP as f32).sqrt().ceil() as usize).max(1);
        let size = (hi - lo).max(Vec2::splat(f32::MIN_POSITIVE)) / side as f32;
        let mut cells: Vec<Vec<u32>> = vec![Vec::new(); side * side];
        for (&i, &c) in on_plane.iter().zip(&centres) {
            let cell = ((c - lo) / size).as_uvec2().min(UVec2::splat(side as u32 - 1));
            cells[cell.y as usize * side + cell.x as usize].push(i);
        }
        for members in cells.into_iter().filter(|m| m.len() > 1) {
            let (lo, hi) = members
                .iter()
                .flat_map(|&i| lights[i as usize].polygon())
                .fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), p| (lo.min(at(p)), hi.max(at(p))));
            let corner = |a: f32, b: f32| a * u + b * v + d * n;
            let rectangle = [corner(lo.x, lo.y), corner(hi.x, lo.y), corner(hi.x, hi.y), corner(lo.x, hi.y)];
            groups.push(LightGroup { members, rectangle, normal: n });
        }
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_scene::scene::suite::{self, Case};

    /// The suite's 256 small emitters under one ceiling: every one in a group of neighbours, each
    /// light's corners inside its group's rectangle, on its plane.
    #[test]
    fn small_emitters_on_one_ceiling_fall_in_groups_that_hold_them() {
        let Case::Built(scene) = suite::case("spheres-256").unwrap() else { panic!("built in") };
        let extent = scene.bounds().extent().length();
        let groups = group_lights(&scene.lights, scene.lights.len(), extent);
        let mut seen: Vec<u32> = groups.iter().flat_map(|g| g.members.clone()).collect();
        seen.sort_unstable();
        assert_eq!(seen, (0..256).collect::<Vec<u32>>(), "each light in exactly one group");
        assert!(groups.len() >= 8 && groups.len() <= 32, "{} groups of about 16", groups.len());
        for g in &groups {
            let (u, v) = (g.rectangle[1] - g.rectangle[0], g.rectangle[3] - g.rectangle[0]);
            for &i in &g.members {
                for p in scene.lights[i as usize].polygon() {
                    let o = p - g.rectangle[0];
                    let (s, t) = (o.dot(u) / u.length_squared(), o.dot(v) / v.length_squared());
                    assert!((-1e-5..=1.0 + 1e-5).contains(&s) && (-1e-5..=1.0 + 1e-5).contains(&t), "{p} outside");
                    assert!(o.dot(g.normal).abs() <= 1e-5 * extent, "{p} off the plane");
                }
            }
        }
    }

    /// Lights on different planes, and point lights, are never grouped together.
    #[test]
    fn lights_on_two_planes_or_points_are_not_mixed() {
        let tri = |y: f32, x: f32| Light::Triangle {
            v: [Vec3::new(x, y, 0.0), Vec3::new(x + 0.1, y, 0.0), Vec3::new(x, y, 0.1)],
            radiance: Vec3::ONE,
        };
        let point = Light::Point { position: Vec3::ZERO, intensity: Vec3::ONE };
        let lights = vec![tri(1.0, 0.0), tri(1.0, 0.5), tri(2.0, 0.0), tri(2.0, 0.5), point];
        let groups = group_lights(&lights, lights.len(), 4.0);
        let mut members: Vec<Vec<u32>> = groups.iter().map(|g| g.members.clone()).collect();
        members.sort();
        assert_eq!(members, vec![vec![0, 1], vec![2, 3]]);
    }
}
