//! Defaults that show a model: the box of what stands in the scene (a large ground plane left
//! out), a camera that frames it from the front, right and above, and a key light above and
//! behind the camera, sized to the objects, so that every face the camera sees is lit.

use super::camera::Camera;
use super::light::Light;
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};

/// Direction from the objects' centre to the default camera: in front (+z), to the right (+x) and
/// above (+y), so that a box shows three faces.
const VIEW: Vec3 = Vec3::new(0.6, 0.45, 1.0);

/// Vertical field of view of the default camera, degrees.
const FOV_Y: f32 = 45.0;

/// Share of the half-frame left free around the framed box.
const MARGIN: f32 = 0.1;

/// Irradiance of the key light where the view centres on the objects, per unit π: a white
/// diffuse surface facing the light comes out at radiance 0.8.
const KEY_IRRADIANCE: f32 = 0.8 * std::f32::consts::PI;

/// The box of what stands in the scene: the bounds of `triangles` without its ground
/// ([`ground`]), down to the ground (so that the view includes its contact).
#[must_use]
pub fn object_bounds(triangles: &[Triangle]) -> Aabb {
    let all = bounds_where(triangles, |_| true);
    match ground(triangles) {
        Some(ground) => {
            let rest = bounds_where(triangles, |i| !ground[i]);
            let floor = all.min.y.max(rest.min.y - rest.extent().y);
            Aabb::new(Vec3::new(rest.min.x, rest.min.y.min(floor), rest.min.z), rest.max)
        }
        None => all,
    }
}

/// Which of `triangles` are a ground much wider than what stands on it, or `None` where there is
/// none. The ground is every horizontal triangle near the lowest height (within 2 % of the scene's
/// width), and every triangle wider (along x or z) than half the scene and less than 2 % of its
/// width high (a slab); it counts only when something else remains and that is less than half as
/// wide as the scene, so that a room (its floor at the bottom, walls as wide) has none.
#[must_use]
pub fn ground(triangles: &[Triangle]) -> Option<Vec<bool>> {
    let all = bounds_where(triangles, |_| true);
    if !all.is_valid() {
        return None;
    }
    let width = all.extent().x.max(all.extent().z);
    let thin = 0.02 * width;
    let mask: Vec<bool> = triangles
        .iter()
        .map(|t| {
            let b = t.v.iter().fold(Aabb::EMPTY, |b, &v| b.grow(v));
            let span = b.extent();
            let wide = span.x.max(span.z) > 0.5 * width;
            t.is_valid() && ((span.y <= 1e-4 * width && b.min.y <= all.min.y + thin) || (wide && span.y <= thin))
        })
        .collect();
    let rest = bounds_where(triangles, |i| !mask[i]);
    (rest.is_valid() && rest.extent().x.max(rest.extent().z) < 0.5 * width).then_some(mask)
}

/// The bounds of the valid triangles whose index `keep` accepts.
fn bounds_where(triangles: &[Triangle], keep: impl Fn(usize) -> bool) -> Aabb {
    let kept = triangles.iter().enumerate().filter(|&(i, t)| t.is_valid() && keep(i));
    kept.fold(Aabb::EMPTY, |b, (_, t)| t.v.iter().fold(b, |b, &v| b.grow(v)))
}

/// A camera that sees `bounds` from the front, right and above (`VIEW`), at the distance where
/// all eight corners of the box lie inside the square frame with a margin of `MARGIN`, looking at
/// its centre; 512 × 512 pixels.
#[must_use]
pub fn framing_camera(bounds: Aabb) -> Camera {
    let c = bounds.center();
    let dir = VIEW.normalize();
    let probe = Camera { position: c + dir, target: c, up: Vec3::Y, fov_y: FOV_Y, width: 512, height: 512 };
    let frame = probe.frame();
    let tan = (FOV_Y.to_radians() * 0.5).tan() * (1.0 - MARGIN);
    // A corner `v` (from the centre) lies in the frame from distance D along `dir` when
    // |v·right| and |v·up| ≤ tan · (D − v·dir).
    let corner = |i: usize| {
        let pick = |bit: usize, lo: f32, hi: f32| if i >> bit & 1 == 0 { lo } else { hi };
        Vec3::new(
            pick(0, bounds.min.x, bounds.max.x),
            pick(1, bounds.min.y, bounds.max.y),
            pick(2, bounds.min.z, bounds.max.z),
        ) - c
    };
    let distance = (0..8)
        .map(corner)
        .map(|v| v.dot(dir) + v.dot(frame.right).abs().max(v.dot(frame.up).abs()) / tan)
        .fold(0.0f32, f32::max)
        .max(1e-3 * bounds.extent().length().max(f32::MIN_POSITIVE));
    Camera { position: c + dir * distance, target: c, up: Vec3::Y, fov_y: FOV_Y, width: 512, height: 512 }
}

/// A square key light above and behind `camera` as seen from the centre of `objects`, facing that
/// centre: its edge a quarter of the objects' diagonal, its radiance such that a surface at the
/// centre facing it receives an irradiance of `KEY_IRRADIANCE`. A face the camera sees faces
/// the camera, and the light lies near the camera's side of it, so it is lit.
#[must_use]
pub fn key_light(camera: &Camera, objects: Aabb) -> Light {
    let c = objects.center();
    let size = (0.25 * objects.extent().length()).max(f32::MIN_POSITIVE);
    let to_camera = camera.position - c;
    let d = to_camera.length().max(size);
    let from = (to_camera.normalize_or(Vec3::Z) + 0.5 * Vec3::Y).normalize_or(Vec3::Y);
    let centre = c + from * (1.3 * d);
    // Edges across `from` with edge_u × edge_v = −from (towards the objects).
    let edge_u = from.any_orthonormal_vector() * size;
    let edge_v = edge_u.cross(from).normalize_or_zero() * size;
    let distance2 = (centre - c).length_squared();
    let radiance = Vec3::splat(KEY_IRRADIANCE * distance2 / (size * size));
    Light::Quad { corner: centre - 0.5 * (edge_u + edge_v), edge_u, edge_v, radiance }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Vec<Triangle> {
        let q = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [Triangle::new(a, b, c), Triangle::new(a, c, d)];
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        [
            q(v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)),
            q(v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.), v(1., 0., 1.)),
            q(v(0., 1., 0.), v(0., 1., 1.), v(1., 1., 1.), v(1., 1., 0.)),
        ]
        .concat()
    }

    #[test]
    fn every_corner_is_in_the_frame() {
        let b = Aabb::new(Vec3::new(-3.0, 0.0, -1.0), Vec3::new(5.0, 0.5, 2.0));
        let cam = framing_camera(b);
        let f = cam.frame();
        for i in 0..8 {
            let p = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            let v = p - cam.position;
            let z = v.dot(f.forward);
            assert!(z > 0.0);
            let (x, y) = (v.dot(f.right) / z / f.half_width, v.dot(f.up) / z / f.half_height);
            assert!(x.abs() <= 1.0 - 0.5 * MARGIN && y.abs() <= 1.0 - 0.5 * MARGIN, "corner {i}: {x}, {y}");
        }
    }

    #[test]
    fn the_key_light_lights_every_face_the_camera_sees() {
        let tris = cube();
        let b = object_bounds(&tris);
        let cam = framing_camera(b);
        let light = key_light(&cam, b);
        for t in &tris {
            let n = t.scaled_normal().normalize();
            let centroid = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
            assert!(n.dot(cam.position - centroid) > 0.0, "the camera sees the face {n}");
            assert!(light.polygon().iter().all(|&p| n.dot(p - centroid) > 0.0), "face {n} is lit");
            assert!(light.normal().dot(centroid - light.center()) > 0.0, "the light faces the face {n}");
        }
    }

    #[test]
    fn a_large_ground_is_left_out_of_the_framing() {
        let mut tris = cube();
        let g = 100.0;
        tris.push(Triangle::new(Vec3::new(-g, 0.0, -g), Vec3::new(-g, 0.0, g), Vec3::new(g, 0.0, g)));
        tris.push(Triangle::new(Vec3::new(-g, 0.0, -g), Vec3::new(g, 0.0, g), Vec3::new(g, 0.0, -g)));
        let b = object_bounds(&tris);
        assert!(b.extent().max_element() < 2.0, "{b:?}");
        // A room (walls as wide as its floor) is framed whole.
        tris.push(Triangle::new(Vec3::new(-g, 0.0, -g), Vec3::new(g, 0.0, -g), Vec3::new(g, 10.0, -g)));
        assert!(object_bounds(&tris).extent().x >= 2.0 * g);
    }
}
