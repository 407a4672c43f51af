//! The depth range of a shadow beam, `[DEPTH_EPS, 1 − DEPTH_EPS]` of the light's distance: a
//! triangle clipped to it, and what lies before it, where geometry touches the shade point.

use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, Quad};

/// The nearest depth at which a beam looks for occluders, as a fraction of its near plane's
/// (`DEPTH_EPS` of the light's distance). A triangle between the two is in contact with the shade
/// point (a leaf through the leaf being shaded, an object sunk into the floor): shadow rays, which
/// start at the point, find it; the beam, which projects only what lies past its near plane (closer
/// is ill-conditioned), would let light through it. Such a beam says so
/// ([`super::ShadowBeam::in_contact`]) and its light is sampled.
pub(super) const CONTACT: f32 = 1e-3;

/// Whether the convex polygon `part` (corners relative to the apex, with their depths, all
/// before depth `near`) of a triangle (its plane's normal and a corner, relative to the apex) may
/// lie in the cone from the apex of `f` through `piece`. Three tests, each of which can only say
/// no: the ball about the apex that holds the cone up to depth `near`, the triangle's
/// own plane (the whole cone on the apex's side of it), and the planes through the apex and an
/// edge of the piece (every corner of `part` outside one). In 3D, not projected: near the apex a
/// projection would magnify the corners by up to `1 / CONTACT` beyond the near plane's.
pub(super) fn cone_meets(
    f: &BeamFrame,
    piece: &Quad,
    part: &[(Vec3, f32)],
    (plane, corner): (Vec3, Vec3),
    near: f32,
) -> bool {
    let to = |uv: Vec2| f.point(uv) - f.apex;
    let reach = piece.corners().fold(0.0f32, |m, c| m.max(to(c).length())) * (near / f.distance);
    if distance_to_polygon(part, plane) > reach * (1.0 + 1e-5) {
        return false;
    }
    // The apex's side of the plane, and each corner ray's: a ray that turns towards the plane
    // may cross it.
    let apex_side = -plane.dot(corner);
    if piece.corners().all(|c| plane.dot(to(c)) * apex_side.signum() >= 0.0) {
        return false;
    }
    let inner = to(piece.corners().sum::<Vec2>() / piece.len() as f32);
    (0..piece.len()).all(|i| {
        let m = to(piece.corner(i)).cross(to(piece.corner((i + 1) % piece.len())));
        let side = m.dot(inner).signum();
        part.iter().any(|(w, _)| side * m.dot(*w) >= -1e-6 * m.length() * w.length())
    })
}

/// The part of a triangle (corners `w` relative to the apex, depths `h`) between the depths
/// `planes`: its corners with their depths, and their number. The depths are affine along the
/// triangle, so clipping interpolates the corners by them (Sutherland–Hodgman against two parallel
/// planes). A triangle cut by two parallel planes keeps at most 5 corners (9 with the repeats that
/// corners exactly on a plane make).
pub(super) fn clip_depth(w: &[Vec3; 3], h: &[f32; 3], (near, far): (f32, f32)) -> ([(Vec3, f32); 9], usize) {
    let mut poly = [(Vec3::ZERO, 0.0f32); 9];
    let mut n = 0;
    let mut push = |p: (Vec3, f32)| {
        if n < poly.len() {
            poly[n] = p;
            n += 1;
        }
    };
    for i in 0..3 {
        let (a, ha, b, hb) = (w[i], h[i], w[(i + 1) % 3], h[(i + 1) % 3]);
        if (near..=far).contains(&ha) {
            push((a, ha));
        }
        // The edge's crossings of the two planes, in order along it.
        let mut cross = [(f32::INFINITY, Vec3::ZERO, 0.0); 2];
        for (c, plane) in cross.iter_mut().zip([near, far]) {
            if (ha < plane) != (hb < plane) {
                let t = (plane - ha) / (hb - ha);
                *c = (t, a + (b - a) * t, plane);
            }
        }
        if cross[1].0 < cross[0].0 {
            cross.swap(0, 1);
        }
        for (t, p, plane) in cross {
            if t.is_finite() {
                push((p, plane));
            }
        }
    }
    (poly, n)
}

/// The distance from the origin to the convex polygon `part` (its corners, with their depths)
/// lying in the plane of normal `plane`.
fn distance_to_polygon(part: &[(Vec3, f32)], plane: Vec3) -> f32 {
    let Some(n) = plane.try_normalize() else { return 0.0 };
    let foot = n * n.dot(part[0].0);
    let k = part.len();
    // Inside when the foot lies on the same side of every edge (either winding).
    let sides = (0..k).map(|i| n.dot((part[(i + 1) % k].0 - part[i].0).cross(foot - part[i].0)));
    let (lo, hi) = sides.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), s| (lo.min(s), hi.max(s)));
    if lo >= 0.0 || hi <= 0.0 {
        return foot.length();
    }
    (0..k)
        .map(|i| {
            let (a, b) = (part[i].0, part[(i + 1) % k].0);
            let e = b - a;
            let t = if e.length_squared() > 0.0 { (-a.dot(e) / e.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
            (a + e * t).length()
        })
        .fold(f32::INFINITY, f32::min)
}
