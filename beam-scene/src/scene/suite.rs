//! The scenes of `beam bench softshadow --suite`: cases that a bench cannot win by choosing them —
//! finely tessellated closed spheres, the shared bunny, spot and teapot on a ground plane, a plant
//! of many small leaves, many small emissive triangles, and a huge ground plane under small
//! objects — all seeded and deterministic, with diffuse materials (albedo 0.7), a 3/4 view and
//! lights that give about 0.33 linear (0.6 sRGB) on the lit ground. Every scene's ground is
//! material 0 ([`content_bounds`] leaves it out).

pub use super::names::GENERATED;

use super::camera::Camera;
use super::foliage;
use super::light::Light;
use super::material::Material;
use super::model::Scene;
use crate::error::SceneError;
use crate::mesh::{Mesh, load_obj};
use beam_math::glam::{Quat, Vec3};
use beam_math::{Aabb, Triangle};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// The suite's cases, in the order the bench runs them.
pub const CASES: [&str; 8] = ["spheres", "spheres-36", "spheres-256", "bunny", "spot", "teapot", "plant", "ground"];

/// The light sizes of the light sweep: the quad's edge as a fraction of the content's width.
pub const SWEEP: [f32; 5] = [0.01, 0.03, 0.1, 0.3, 1.0];

/// Rings and segments of each sphere of the `spheres` cases.
pub const SPHERE_RINGS: u32 = 48;

/// Triangles of one sphere of the `spheres` cases (`2 · segments · (rings − 1)`).
pub const SPHERE_TRIANGLES: usize = 2 * SPHERE_RINGS as usize * (SPHERE_RINGS as usize - 1);

/// Triangles of the `spheres` case: nine spheres and the two of the ground.
pub const SPHERES_TRIANGLES: usize = 9 * SPHERE_TRIANGLES + 2;

/// Leaves of the `plant` case (two triangles each; with the trunk, branches, ground and light:
/// `2 · PLANT_LEAVES + 76` triangles, about 001's plant).
pub const PLANT_LEAVES: u32 = 2200;

/// Objects of the `ground` case, each a closed 32 × 32 sphere.
pub const GROUND_OBJECTS: usize = 6;

/// Triangles of the `ground` case.
pub const GROUND_TRIANGLES: usize = GROUND_OBJECTS * 2 * 32 * 31 + 2;

/// The edge of each case's quad light as a fraction of the content's width.
pub const LIGHT_FRACTION: f32 = 0.3;

/// Irradiance the lights give the ground under the content (radiance 0.7/π of it: 0.33 linear).
const IRRADIANCE: f32 = 1.5;

const GROUND: u32 = 0;
const OBJECT: u32 = 1;
const EMITTER: u32 = 2;

/// A built case, or the reason it cannot be (a shared mesh that is absent).
pub enum Case {
    /// The scene.
    Built(Box<Scene>),
    /// Why it was skipped.
    Absent(String),
}

/// The suite case `name` (one of [`CASES`]). A shared mesh that is absent gives [`Case::Absent`];
/// one that is malformed, an error naming the file.
pub fn case(name: &str) -> Result<Case, SceneError> {
    let scene = match name {
        "spheres" => spheres(0),
        "spheres-36" => spheres(6),
        "spheres-256" => spheres(16),
        "bunny" | "spot" | "teapot" => {
            let rel = match name {
                "bunny" => "stanford_bunny/stanford-bunny.obj",
                "spot" => "spot/spot_triangulated.obj",
                _ => "teapot/teapot.obj",
            };
            let path = match crate::scenes::scenes_dir() {
                Ok(dir) => dir.join(rel),
                Err(e) => return Ok(Case::Absent(e.to_string())),
            };
            if !path.is_file() {
                return Ok(Case::Absent(format!("{} not found", path.display())));
            }
            // Spot faces −z: turned to face +x, so that the 3/4 view sees her head and side.
            let turn = if name == "spot" { -std::f32::consts::FRAC_PI_2 } else { 0.0 };
            on_ground(name, &load_obj(&path)?, turn)
        }
        "plant" => {
            let mut s = foliage::foliage(PLANT_LEAVES, 1);
            s.name = "plant".into();
            s.camera = three_quarter(content_bounds(&s));
            s
        }
        "ground" => ground(1),
        _ => return Err(SceneError::UnknownScene { name: name.to_string() }),
    };
    Ok(Case::Built(Box::new(scene)))
}

/// A closed UV sphere: one vertex per pole, `rings − 1` rings of `segments` vertices (the seam
/// shares its vertices), rotated by `phase` radians about +y; `2 · segments · (rings − 1)`
/// triangles, counter-clockwise seen from outside. Neighbouring triangles share bit-identical
/// positions because they share indices.
#[must_use]
pub fn closed_sphere(center: Vec3, radius: f32, rings: u32, segments: u32, phase: f32) -> Mesh {
    let (rings, segments) = (rings.max(2), segments.max(3));
    let mut positions = vec![center + Vec3::Y * radius];
    for r in 1..rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = phase + std::f32::consts::TAU * s as f32 / segments as f32;
            positions.push(center + radius * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()));
        }
    }
    positions.push(center - Vec3::Y * radius);
    let bottom = positions.len() as u32 - 1;
    // Ring r (1-based) segment s; the poles stand for ring 0 and ring `rings`.
    let at = |r: u32, s: u32| match r {
        0 => 0,
        r if r == rings => bottom,
        r => 1 + (r - 1) * segments + s % segments,
    };
    let mut indices = Vec::new();
    for r in 0..rings {
        for s in 0..segments {
            let (a, b, c, d) = (at(r, s), at(r, s + 1), at(r + 1, s), at(r + 1, s + 1));
            // (b − a) runs along φ, (c − a) down θ: their cross product points outwards.
            if r > 0 {
                indices.push([a, b, c]);
            }
            if r + 1 < rings {
                indices.push([b, d, c]);
            }
        }
    }
    Mesh { positions, indices }
}

/// The bounds of the content: every triangle but the ground's (material 0) and the emitters'.
#[must_use]
pub fn content_bounds(scene: &Scene) -> Aabb {
    scene
        .triangles
        .iter()
        .zip(&scene.material_of)
        .filter(|&(_, &m)| m != GROUND && !matches!(scene.materials[m as usize], Material::Emissive { .. }))
        .fold(Aabb::EMPTY, |b, (t, _)| t.v.iter().fold(b, |b, &v| b.grow(v)))
}

/// `scene`'s first light, if a quad, made a square of edge `fraction` × the content's width (the
/// larger of its x and z extents) along the same edge directions and about the same centre, its
/// radiance scaled by the inverse of the area so that the irradiance stays about the same: the
/// light sweep. `None` when the first light is not a quad or the scene has no content.
#[must_use]
pub fn light_of_size(scene: &Scene, fraction: f32) -> Option<Light> {
    let Some(&Light::Quad { corner, edge_u, edge_v, radiance }) = scene.lights.first() else { return None };
    let e = content_bounds(scene).extent();
    let edge = fraction * e.x.max(e.z);
    let (u, v) = (edge_u.try_normalize()? * edge, edge_v.try_normalize()? * edge);
    let center = corner + 0.5 * (edge_u + edge_v);
    let scale = edge_u.cross(edge_v).length() / u.cross(v).length();
    scale.is_finite().then(|| Light::Quad {
        corner: center - 0.5 * (u + v),
        edge_u: u,
        edge_v: v,
        radiance: radiance * scale,
    })
}

/// Two triangles facing up: the square ground of half-side `half` about `(c.x, 0, c.z)`.
fn ground_plane(c: Vec3, half: f32) -> [(Triangle, u32); 2] {
    let p = |x: f32, z: f32| Vec3::new(c.x + x * half, 0.0, c.z + z * half);
    let (a, b, c, d) = (p(-1.0, -1.0), p(-1.0, 1.0), p(1.0, 1.0), p(1.0, -1.0));
    [(Triangle::new(a, b, c), GROUND), (Triangle::new(a, c, d), GROUND)]
}

/// A camera seeing `content` from the front right and above (azimuth about 30°, elevation about
/// 28°), 40° field of view, with the content's bounding sphere filling most of the frame.
fn three_quarter(content: Aabb) -> Camera {
    let (c, r) = (content.center(), 0.5 * content.extent().length());
    let fov_y = 40.0f32;
    let distance = 1.1 * r / (0.5 * fov_y).to_radians().sin();
    let position = c + Vec3::new(0.55, 0.6, 1.0).normalize() * distance;
    Camera { position, target: c, up: Vec3::Y, fov_y, width: 512, height: 512 }
}

/// The radiance a set of small down-facing emitters (centre, area) needs to give [`IRRADIANCE`]
/// at `p` on the ground (each `L · A cos θ cos θ' / d²`).
fn radiance_for(p: Vec3, emitters: impl Iterator<Item = (Vec3, f32)>) -> Vec3 {
    let per_radiance: f32 = emitters
        .map(|(q, area)| {
            let d = q - p;
            let cos = d.y.max(0.0) / d.length();
            area * cos * cos / d.length_squared()
        })
        .sum();
    Vec3::splat(IRRADIANCE / per_radiance.max(f32::MIN_POSITIVE))
}

/// A down-facing square quad light of edge [`LIGHT_FRACTION`] × the content's width, one width
/// above the content's top, off its centre by 0.3 widths towards +x and −z (so that the shadow
/// falls towards the camera's side).
fn quad_light(content: Aabb) -> Light {
    let (c, e) = (content.center(), content.extent());
    let w = e.x.max(e.z);
    let center = Vec3::new(c.x + 0.3 * w, content.max.y + w, c.z - 0.3 * w);
    let edge = LIGHT_FRACTION * w;
    let (edge_u, edge_v) = (Vec3::X * edge, Vec3::Z * edge); // edge_u × edge_v = −y
    let radiance = radiance_for(Vec3::new(c.x, 0.0, c.z), std::iter::once((center, edge * edge)));
    Light::Quad { corner: center - 0.5 * (edge_u + edge_v), edge_u, edge_v, radiance }
}

/// A scene of `objects` (material [`OBJECT`]) on a ground plane of half-side `half` content widths,
/// lit by `lights` (triangle lights also go in as triangles of material [`EMITTER`], of `radiance`,
/// as the glTF loader adds them), or by one [`quad_light`] when there are none.
fn assemble(name: &str, objects: Vec<Triangle>, half: f32, lights: Vec<Light>, radiance: Vec3) -> Scene {
    let content = objects.iter().fold(Aabb::EMPTY, |b, t| t.v.iter().fold(b, |b, &v| b.grow(v)));
    let e = content.extent();
    let mut tris: Vec<(Triangle, u32)> = ground_plane(content.center(), half * e.x.max(e.z)).to_vec();
    tris.extend(objects.into_iter().map(|t| (t, OBJECT)));
    tris.extend(lights.iter().filter_map(|l| match *l {
        Light::Triangle { v, .. } => Some((Triangle { v }, EMITTER)),
        _ => None,
    }));
    let lights = if lights.is_empty() { vec![quad_light(content)] } else { lights };
    let materials = vec![
        Material::Diffuse { albedo: Vec3::splat(0.7) },
        Material::Diffuse { albedo: Vec3::splat(0.7) },
        Material::Emissive { radiance },
    ];
    Scene::new(name.into(), tris, materials, lights, three_quarter(content))
}

/// A 3 × 3 grid of closed spheres (radius 0.5, 1.25 apart, [`SPHERE_TRIANGLES`] triangles each,
/// seeded rotations) resting on a ground plane; lit by one quad light when `n` is 0, else by an
/// `n × n` grid of small down-facing emissive triangles (seeded jitter and rotation) one grid width
/// above the spheres, over the grid's square.
fn spheres(n: u32) -> Scene {
    let mut rng = Pcg32::seed_from_u64(u64::from(n) + 1);
    let (radius, pitch) = (0.5f32, 1.25f32);
    let mut objects = Vec::with_capacity(9 * SPHERE_TRIANGLES);
    for i in 0..9 {
        let center = Vec3::new(pitch * (i % 3) as f32 - pitch, radius, pitch * (i / 3) as f32 - pitch);
        let phase = rng.random_range(0.0..std::f32::consts::TAU);
        objects.extend(closed_sphere(center, radius, SPHERE_RINGS, SPHERE_RINGS, phase).triangles());
    }
    let name = if n == 0 { "spheres".to_string() } else { format!("spheres-{}", n * n) };
    if n == 0 {
        return assemble(&name, objects, 5.0, Vec::new(), Vec3::ZERO);
    }
    let width = 2.0 * pitch + 2.0 * radius;
    let (height, cell) = (2.0 * radius + width, width / n as f32);
    let leg = 0.35 * cell;
    let mut tris = Vec::new();
    for k in 0..n * n {
        let jitter = Vec3::new(rng.random_range(-0.15..0.15), 0.0, rng.random_range(-0.15..0.15)) * cell;
        let c = Vec3::new(
            -0.5 * width + cell * ((k % n) as f32 + 0.5),
            height,
            -0.5 * width + cell * ((k / n) as f32 + 0.5),
        );
        let turn = Quat::from_rotation_y(rng.random_range(0.0..std::f32::consts::TAU));
        // (a, a + leg·x, a + leg·z) faces −y; the rotation about y keeps it facing down.
        let corners = [Vec3::ZERO, Vec3::X * leg, Vec3::Z * leg]
            .map(|v| c + jitter + turn * (v - Vec3::new(leg, 0.0, leg) / 3.0));
        tris.push(corners);
    }
    let area = 0.5 * leg * leg;
    let radiance = radiance_for(Vec3::ZERO, tris.iter().map(|v| ((v[0] + v[1] + v[2]) / 3.0, area)));
    let lights = tris.into_iter().map(|v| Light::Triangle { v, radiance }).collect();
    assemble(&name, objects, 5.0, lights, radiance)
}

/// A shared mesh turned by `turn` radians about +y, scaled to a width of 1 (its larger horizontal
/// extent), centred on the origin and standing on a ground plane 10 widths across; one quad light.
fn on_ground(name: &str, mesh: &Mesh, turn: f32) -> Scene {
    let q = Quat::from_rotation_y(turn);
    let tris: Vec<Triangle> =
        mesh.triangles().into_iter().map(|t| Triangle { v: t.v.map(|v| q * v) }).filter(|t| t.is_valid()).collect();
    let b = tris.iter().fold(Aabb::EMPTY, |b, t| t.v.iter().fold(b, |b, &v| b.grow(v)));
    let s = 1.0 / b.extent().x.max(b.extent().z).max(f32::MIN_POSITIVE);
    let offset = Vec3::new(b.center().x, b.min.y, b.center().z);
    let objects = tris.into_iter().map(|t| Triangle { v: t.v.map(|v| (v - offset) * s) }).collect();
    assemble(name, objects, 5.0, Vec::new(), Vec3::ZERO)
}

/// [`GROUND_OBJECTS`] closed spheres (radius 0.25 to 0.5, seeded, not overlapping) scattered over
/// a 4 × 4 square, on a ground plane 100 times their spread across; one quad light above them.
fn ground(seed: u64) -> Scene {
    let mut rng = Pcg32::seed_from_u64(seed);
    let mut placed: Vec<(Vec3, f32)> = Vec::new();
    while placed.len() < GROUND_OBJECTS {
        let r = rng.random_range(0.25f32..0.5);
        let c = Vec3::new(rng.random_range(-2.0..2.0), r, rng.random_range(-2.0..2.0));
        if placed.iter().all(|&(q, s)| q.distance(c) > r + s + 0.1) {
            placed.push((c, r));
        }
    }
    let objects =
        placed.iter().flat_map(|&(c, r)| closed_sphere(c, r, 32, 32, rng.random_range(0.0..1.0)).triangles()).collect();
    assemble("ground", objects, 50.0, Vec::new(), Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn built(name: &str) -> Option<Scene> {
        match case(name).unwrap() {
            Case::Built(s) => Some(*s),
            Case::Absent(why) => {
                eprintln!("{name} skipped: {why}");
                None
            }
        }
    }

    /// Every directed edge (by exact positions) of `tris` once, and its reverse once: closed and
    /// consistently oriented.
    fn assert_closed(tris: &[Triangle]) {
        let key = |v: Vec3| v.to_array().map(f32::to_bits);
        let mut edges: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
        for t in tris {
            for i in 0..3 {
                *edges.entry((key(t.v[i]), key(t.v[(i + 1) % 3]))).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "directed edge used {n} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge without its opposite");
        }
    }

    #[test]
    fn closed_spheres_are_closed_and_face_outwards() {
        let c = Vec3::new(1.0, 2.0, 3.0);
        let m = closed_sphere(c, 0.5, SPHERE_RINGS, SPHERE_RINGS, 0.3);
        let tris = m.triangles();
        assert_eq!(tris.len(), SPHERE_TRIANGLES);
        assert_closed(&tris);
        for t in &tris {
            assert!(t.is_valid());
            assert!(t.scaled_normal().dot((t.v[0] + t.v[1] + t.v[2]) / 3.0 - c) > 0.0, "inward triangle");
        }
    }

    #[test]
    fn cases_are_non_empty_with_the_documented_counts() {
        for name in CASES {
            let Some(s) = built(name) else { continue };
            assert_eq!(s.name, name);
            assert!(s.stats.triangles > 1000 && !s.lights.is_empty(), "{name}");
            assert!(s.camera.has_view(), "{name}");
            let content = content_bounds(&s);
            assert!(content.is_valid(), "{name}");
            let seen = (content.center() - s.camera.position)
                .normalize()
                .dot((s.camera.target - s.camera.position).normalize());
            assert!(seen > 0.95, "{name}: the camera looks away from the content");
            let expected = match name {
                "spheres" => Some(SPHERES_TRIANGLES),
                "spheres-36" => Some(SPHERES_TRIANGLES + 36),
                "spheres-256" => Some(SPHERES_TRIANGLES + 256),
                "plant" => Some(2 * PLANT_LEAVES as usize + 76),
                "ground" => Some(GROUND_TRIANGLES),
                _ => None,
            };
            if let Some(n) = expected {
                assert_eq!((s.stats.triangles, s.stats.degenerate), (n, 0), "{name}");
            }
        }
    }

    #[test]
    fn sphere_grids_are_closed_and_emitters_face_down() {
        for (name, lights) in [("spheres", 1), ("spheres-36", 36), ("spheres-256", 256)] {
            let s = built(name).unwrap();
            let spheres: Vec<Triangle> =
                s.triangles.iter().zip(&s.material_of).filter(|&(_, &m)| m == OBJECT).map(|(t, _)| *t).collect();
            assert_eq!(spheres.len(), 9 * SPHERE_TRIANGLES);
            assert_closed(&spheres);
            assert_eq!(s.lights.len(), lights);
            let emitters = s.material_of.iter().filter(|&&m| m == EMITTER).count();
            assert_eq!(emitters, if lights == 1 { 0 } else { lights }, "{name}: an emissive triangle per light");
            let top = content_bounds(&s).max.y;
            for l in &s.lights {
                assert!(l.normal().y < -0.999 && l.center().y > top + 1.0 && l.area() > 0.0, "{name}: {l:?}");
            }
        }
    }

    #[test]
    fn seeded_and_deterministic() {
        for name in ["spheres-36", "ground"] {
            let (a, b) = (built(name).unwrap(), built(name).unwrap());
            assert_eq!((a.triangles, a.lights), (b.triangles, b.lights), "{name}");
        }
    }

    #[test]
    fn light_sweep_keeps_the_centre_and_the_power_per_area() {
        let s = built("spheres").unwrap();
        let width = 3.5;
        let base = s.lights[0];
        for f in SWEEP {
            let l = light_of_size(&s, f).unwrap();
            assert!((l.area() - (f * width) * (f * width)).abs() < 1e-4 * width * width, "{f}");
            assert!(l.center().distance(base.center()) < 1e-4);
            assert!(
                (l.power().x * l.area() - base.power().x * base.area()).abs() < 1e-3 * base.power().x * base.area()
            );
            assert!(l.normal().y < -0.999);
        }
        assert!(light_of_size(&built("spheres-36").unwrap(), 0.1).is_none(), "triangle lights are not swept");
    }
}
