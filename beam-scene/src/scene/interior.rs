//! Defaults for a model seen from inside (a room, a courtyard, a building modelled for its
//! interior): the framing camera outside it would see only its outer walls, a featureless box, and
//! the key light outside would light only them. Such a model encloses its centre: from there
//! most directions meet a face turned towards the centre. A closed object (a box, a statue) turns
//! its faces away from its centre, and a set of objects leaves most directions open; a ground
//! under them encloses nothing (a table on a wide floor is not a room).

use super::camera::Camera;
use super::framing;
use super::light::Light;
use super::model::Scene;
use beam_math::Ray;
use beam_math::glam::Vec3;

/// Directions tried from the centre (a Fibonacci sphere).
const DIRECTIONS: u32 = 64;

/// Share of them that must meet a face turned towards the centre.
const ENCLOSED: f32 = 0.75;

/// Edge of the default ceiling light, as a fraction of the scene box's width and depth.
const CEILING_LIGHT: f32 = 0.1;

/// Irradiance of the ceiling light on the floor below its centre, per unit π (that of
/// [`super::framing::key_light`] on the objects it frames).
const FLOOR_IRRADIANCE: f32 = 0.8 * std::f32::consts::PI;

/// Whether `scene` encloses the centre of its box: at least [`ENCLOSED`] of [`DIRECTIONS`]
/// directions from there meet a triangle on its front ([`front_share`]).
#[must_use]
fn encloses(scene: &Scene) -> bool {
    front_share(scene) >= ENCLOSED
}

/// The share of [`DIRECTIONS`] directions from the centre of the scene's box (a Fibonacci
/// sphere) whose first hit is a triangle's front (its winding's normal towards the centre), not
/// on a ground much wider than the rest ([`framing::ground`]).
fn front_share(scene: &Scene) -> f32 {
    let centre = scene.bounds().center();
    let ground = framing::ground(&scene.triangles).unwrap_or_default();
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let front = (0..DIRECTIONS)
        .filter(|&i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / DIRECTIONS as f32;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = golden * i as f32;
            let d = Vec3::new(r * phi.cos(), y, r * phi.sin());
            let hit = scene.wide.closest_hit(Ray::new(centre, d), f32::INFINITY);
            hit.is_some_and(|hit| {
                let prim = hit.prim as usize;
                scene.triangles[prim].scaled_normal().dot(d) < 0.0 && !ground.get(prim).copied().unwrap_or(false)
            })
        })
        .count();
    front as f32 / DIRECTIONS as f32
}

/// A square light of edge `size` times the scene box's width and depth, facing down at the box's
/// centre just under the ceiling: 1% of the box's height below the first surface straight up from
/// the centre, or 2% under the box's top where nothing is above.
#[must_use]
pub fn ceiling_light(scene: &Scene, size: f32, radiance: Vec3) -> Light {
    let bounds = scene.bounds();
    let mut light = Light::under_ceiling(bounds, size, radiance);
    if let Some(hit) = scene.wide.closest_hit(Ray::new(bounds.center(), Vec3::Y), f32::INFINITY)
        && let Light::Quad { corner, .. } = &mut light
    {
        corner.y = bounds.center().y + hit.t - 0.01 * bounds.extent().y;
    }
    light
}

/// Where `scene` [`encloses`] its centre, give it a camera that shows its inside
/// ([`view_inside`], the size of the one it has) and, with `light`, a ceiling light
/// ([`ceiling_light`]) in place of its lights, bright enough that the floor below it receives the
/// key light's irradiance. The loaders call it for a scene whose file has no camera.
pub(crate) fn look_inside(scene: &mut Scene, light: bool) {
    if !encloses(scene) {
        return;
    }
    scene.camera = view_inside(scene);
    if light {
        let mut ceiling = ceiling_light(scene, CEILING_LIGHT, Vec3::ONE);
        if let Light::Quad { corner, edge_u, edge_v, radiance } = &mut ceiling {
            // E ≈ L · A / h² straight below a small light at height h.
            let h = (corner.y - scene.bounds().min.y).max(f32::MIN_POSITIVE);
            let area = edge_u.cross(*edge_v).length().max(f32::MIN_POSITIVE);
            *radiance = Vec3::splat(FLOOR_IRRADIANCE * h * h / area);
        }
        scene.lights = vec![ceiling];
    }
}

/// A camera that shows the inside of `scene`: where a level ray from the box's centre along ±x or
/// ±z leaves the scene (a room open at one side, as the Cornell box is), from that side, far
/// enough that the whole opening fits the frame; otherwise [`Camera::interior`] (inside, along
/// the longer horizontal axis).
fn view_inside(scene: &Scene) -> Camera {
    let (bounds, camera) = (scene.bounds(), &scene.camera);
    let (c, half) = (bounds.center(), 0.5 * bounds.extent());
    let open = [Vec3::X, Vec3::NEG_X, Vec3::Z, Vec3::NEG_Z]
        .into_iter()
        .find(|&d| scene.wide.closest_hit(Ray::new(c, d), f32::INFINITY).is_none());
    let Some(side) = open else { return Camera::interior(bounds, camera.width, camera.height) };
    // The opening's half width and height, seen in a 60° field with a 10% margin.
    let across = if side.x != 0.0 { half.z } else { half.x };
    let reach = across.max(half.y) / (0.9 * 30f32.to_radians().tan());
    let position = c + side * (half.dot(side.abs()) + reach);
    Camera { position, target: c, up: Vec3::Y, fov_y: 60.0, width: camera.width, height: camera.height }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Material;
    use beam_math::Triangle;

    /// The faces of the unit cube but those in `open` (0 to 5: −x, +x, −y, +y, −z, +z), each as
    /// two triangles wound with their normals inwards (`inward`) or outwards.
    fn cube(open: &[usize], inward: bool) -> Scene {
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let faces = [
            [v(0., 0., 0.), v(0., 0., 1.), v(0., 1., 1.), v(0., 1., 0.)],
            [v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.), v(1., 0., 1.)],
            [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 1.), v(0., 0., 1.)],
            [v(0., 1., 0.), v(0., 1., 1.), v(1., 1., 1.), v(1., 1., 0.)],
            [v(0., 0., 0.), v(0., 1., 0.), v(1., 1., 0.), v(1., 0., 0.)],
            [v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)],
        ];
        let mut triangles = Vec::new();
        for (_, [a, b, c, d]) in faces.into_iter().enumerate().filter(|(i, _)| !open.contains(i)) {
            // As listed, each face's winding points out of the cube.
            let (b, d) = if inward { (d, b) } else { (b, d) };
            triangles.push((Triangle::new(a, b, c), 0));
            triangles.push((Triangle::new(a, c, d), 0));
        }
        let camera = Camera {
            position: v(3., 3., 3.),
            target: v(0.5, 0.5, 0.5),
            up: Vec3::Y,
            fov_y: 45.0,
            width: 64,
            height: 48,
        };
        let light = Light::Quad { corner: v(0., 5., 0.), edge_u: Vec3::X, edge_v: Vec3::Z, radiance: Vec3::ONE };
        Scene::new("cube".into(), triangles, vec![Material::Diffuse { albedo: Vec3::splat(0.7) }], vec![light], camera)
    }

    /// A room (faces turned in) encloses its centre, open at one side or not; a closed box and
    /// an open one with their faces turned out do not.
    #[test]
    fn rooms_enclose_their_centre_and_boxes_do_not() {
        assert!(encloses(&cube(&[], true)));
        assert!(encloses(&cube(&[5], true)));
        assert!(!encloses(&cube(&[], false)));
        assert!(!encloses(&cube(&[5], false)));
    }

    /// A table top (a slab, faces out) over a ground plane five times as wide: from the centre
    /// of the scene's box, the ground fills the lower half of the directions and the top's
    /// underside most of the upper half, but a ground encloses nothing: it is no room.
    #[test]
    fn a_table_on_a_wide_ground_is_no_room() {
        let room = cube(&[], true);
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let mut triangles = vec![
            (Triangle::new(v(-10., 0., -10.), v(-10., 0., 10.), v(10., 0., 10.)), 0),
            (Triangle::new(v(-10., 0., -10.), v(10., 0., 10.), v(10., 0., -10.)), 0),
        ];
        // The slab x ∈ [−2, 2], y ∈ [0.9, 1], z ∈ [−1.5, 1.5]: the unit cube's faces, turned out.
        let slab = |p: Vec3| v(-2.0 + 4.0 * p.x, 0.9 + 0.1 * p.y, -1.5 + 3.0 * p.z);
        let faces = cube(&[], false).triangles;
        triangles.extend(faces.iter().map(|t| (Triangle::new(slab(t.v[0]), slab(t.v[1]), slab(t.v[2])), 0)));
        let table = Scene::new("table".into(), triangles, room.materials.clone(), room.lights.clone(), room.camera);
        let share = front_share(&table);
        assert!(share < 0.5, "{share}");
        assert!(!encloses(&table));
    }

    /// A room open at +z is seen from outside that side, looking in, with the whole opening in
    /// the frame; a closed one from inside. The ceiling light hangs inside, under the ceiling,
    /// facing down, and lights the floor below it with the key light's irradiance.
    #[test]
    fn a_room_is_seen_from_its_open_side_and_lit_under_its_ceiling() {
        let mut open = cube(&[5], true);
        look_inside(&mut open, true);
        let c = open.camera;
        assert!(c.position.z > 1.0 && (c.position.x - 0.5).abs() < 1e-5 && (c.position.y - 0.5).abs() < 1e-5, "{c:?}");
        assert_eq!((c.target, c.width, c.height), (Vec3::splat(0.5), 64, 48));
        // The opening's corners lie inside the 60° frame.
        let half = (c.position.z - 1.0) * 30f32.to_radians().tan();
        assert!(half >= 0.5, "the opening's half size 0.5 against {half}");
        let [Light::Quad { corner, edge_u, edge_v, radiance }] = open.lights[..] else { panic!("{:?}", open.lights) };
        assert!((corner.y - 0.99).abs() < 1e-5, "1% of the height under the ceiling: {corner}");
        assert!(edge_u.cross(edge_v).y < 0.0, "facing down");
        let centre = corner + 0.5 * (edge_u + edge_v);
        assert!((centre - Vec3::new(0.5, 0.99, 0.5)).length() < 1e-5, "{centre}");
        let e = radiance.x * edge_u.cross(edge_v).length() / (0.99 * 0.99);
        assert!((e - FLOOR_IRRADIANCE).abs() < 1e-3 * FLOOR_IRRADIANCE, "{e}");
        let mut closed = cube(&[], true);
        look_inside(&mut closed, false);
        let p = closed.camera.position;
        assert!(p.cmpgt(Vec3::ZERO).all() && p.cmplt(Vec3::ONE).all(), "inside: {p}");
        assert!(matches!(closed.lights[..], [Light::Quad { corner, .. }] if corner.y == 5.0), "its own light kept");
    }
}
