//! Seeded generators of test cases: rays, boxes, frusta, polygons, polynomials, beams and scene
//! triangles. Every property takes its cases from here so that a failure reproduces exactly.

use beam_math::collide::{ConvexPolygon, Frustum, convex_hull};
use beam_math::glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use beam_math::nonlinear::{NonlinearBeam, S3};
use beam_math::{Aabb, Ray, Triangle};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// The suite's random source.
pub type Rng64 = Pcg64;

/// A generator seeded with `seed`.
#[must_use]
pub fn rng(seed: u64) -> Rng64 {
    Pcg64::seed_from_u64(seed)
}

/// Uniform in `[lo, hi)`.
pub fn uniform(rng: &mut Rng64, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * rng.random::<f32>()
}

/// A point uniform in the cube `[−r, r]³`.
pub fn point(rng: &mut Rng64, r: f32) -> Vec3 {
    Vec3::new(uniform(rng, -r, r), uniform(rng, -r, r), uniform(rng, -r, r))
}

/// A unit vector uniform on the sphere.
pub fn unit(rng: &mut Rng64) -> Vec3 {
    loop {
        let v = point(rng, 1.0);
        let l = v.length_squared();
        if l > 1e-4 && l <= 1.0 {
            return v / l.sqrt();
        }
    }
}

/// A random rotation.
pub fn rotation(rng: &mut Rng64) -> Quat {
    Quat::from_axis_angle(unit(rng), uniform(rng, 0.0, std::f32::consts::TAU))
}

/// A random box inside `[−r, r]³`.
pub fn aabb(rng: &mut Rng64, r: f32) -> Aabb {
    let a = point(rng, r);
    let b = point(rng, r);
    Aabb::new(a.min(b), a.max(b))
}

/// A random ray; one in four has one or two direction components exactly zero (axis-parallel).
pub fn ray(rng: &mut Rng64, r: f32) -> Ray {
    let mut d = unit(rng);
    match rng.random_range(0..8) {
        0 => d.x = 0.0,
        1 => {
            d.y = 0.0;
            d.z = 0.0;
        }
        _ => {}
    }
    if d == Vec3::ZERO {
        d = Vec3::X;
    }
    Ray::new(point(rng, r), d)
}

/// A random perspective camera frustum in general orientation.
pub fn frustum(rng: &mut Rng64) -> Frustum {
    let eye = point(rng, 2.0);
    let target = eye + unit(rng);
    let mut up = unit(rng);
    if up.cross(target - eye).length_squared() < 1e-3 {
        up = (target - eye).any_orthonormal_vector();
    }
    let view = Mat4::look_at_rh(eye, target, up);
    let proj = Mat4::perspective_rh(
        uniform(rng, 0.3, 1.8),
        uniform(rng, 0.5, 2.0),
        uniform(rng, 0.1, 1.0),
        uniform(rng, 2.0, 6.0),
    );
    Frustum::from_view_projection(proj * view)
}

/// A random convex polygon: the hull of 3–8 points in a disc of radius `r` around `c`.
pub fn convex_polygon(rng: &mut Rng64, c: Vec2, r: f32) -> ConvexPolygon<16> {
    loop {
        let n = rng.random_range(3..=8);
        let pts: Vec<Vec2> =
            (0..n).map(|_| c + r * Vec2::new(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0))).collect();
        let h: ConvexPolygon<8> = convex_hull(&pts);
        if h.area() > 1e-3 * r * r {
            return ConvexPolygon::from_slice(h.vertices()).expect("8 ≤ 16");
        }
    }
}

/// The shape of a beam's rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeamKind {
    /// Rays spreading away from each other (convex mirror, camera).
    Diverging,
    /// Rays aimed at a focus in front of the base (concave mirror), crossing beyond it.
    Converging,
    /// Independent random tilts.
    Mixed,
}

impl BeamKind {
    /// All kinds.
    pub const ALL: [BeamKind; 3] = [BeamKind::Diverging, BeamKind::Converging, BeamKind::Mixed];
}

/// A random base triangle (not too thin) in a random frame; returns the vertices and the normal.
pub fn base_triangle(rng: &mut Rng64) -> ([Vec3; 3], Vec3, Mat3) {
    let frame = Mat3::from_quat(rotation(rng));
    let origin = point(rng, 3.0);
    loop {
        let local: [Vec2; 3] = std::array::from_fn(|_| Vec2::new(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0)));
        let area = 0.5 * (local[1] - local[0]).perp_dot(local[2] - local[0]);
        let shortest = (0..3).map(|i| local[i].distance(local[(i + 1) % 3])).fold(f32::INFINITY, f32::min);
        if area.abs() > 0.3 && shortest > 0.5 {
            let v = local.map(|p| origin + frame * Vec3::new(p.x, p.y, 0.0));
            return (v, frame * Vec3::Z, frame);
        }
    }
}

/// Boundary directions of a beam of the given kind over a base with normal `n`.
pub fn beam_directions(rng: &mut Rng64, kind: BeamKind, base: &[Vec3; 3], n: Vec3, frame: Mat3) -> [Vec3; 3] {
    let c = (base[0] + base[1] + base[2]) / 3.0;
    match kind {
        BeamKind::Diverging => {
            let k = uniform(rng, 0.2, 1.2);
            let tilt = frame * Vec3::new(uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3), 0.0);
            base.map(|p| (n + tilt + k * (p - c)).normalize())
        }
        BeamKind::Converging => {
            let focus = c
                + n * uniform(rng, 0.7, 4.0)
                + frame * Vec3::new(uniform(rng, -0.4, 0.4), uniform(rng, -0.4, 0.4), 0.0);
            base.map(|p| (focus - p).normalize())
        }
        BeamKind::Mixed => {
            base.map(|_| (n + frame * Vec3::new(uniform(rng, -0.8, 0.8), uniform(rng, -0.8, 0.8), 0.0)).normalize())
        }
    }
}

/// A random S1 beam of the given kind.
pub fn s1_beam(rng: &mut Rng64, kind: BeamKind) -> NonlinearBeam {
    let (base, n, frame) = base_triangle(rng);
    let dirs = beam_directions(rng, kind, &base, n, frame);
    NonlinearBeam::s1(base, dirs).expect("generated beams are valid")
}

/// A random S3 beam of the given kind, with S-mesh normals tilted up to about 25°.
pub fn s3_beam(rng: &mut Rng64, kind: BeamKind) -> NonlinearBeam<S3> {
    let (base, n, frame) = base_triangle(rng);
    let dirs = beam_directions(rng, kind, &base, n, frame);
    let normals = std::array::from_fn(|_| {
        (n + frame * Vec3::new(uniform(rng, -0.45, 0.45), uniform(rng, -0.45, 0.45), 0.0)).normalize()
    });
    NonlinearBeam::new(base, dirs, S3 { normals }).expect("generated beams are valid")
}

/// A scene triangle for a beam: centred on a ray of the beam at parameter `t` (a mix of near, mid
/// and far), of a size relative to its distance; some large ones straddle the beam boundary.
pub fn scene_triangle<L: beam_math::nonlinear::Interpolant>(rng: &mut Rng64, beam: &NonlinearBeam<L>) -> Triangle {
    let w = barycentric(rng);
    let t = match rng.random_range(0..3) {
        0 => uniform(rng, 0.05, 1.0),
        1 => uniform(rng, 1.0, 5.0),
        _ => uniform(rng, 5.0, 40.0),
    };
    let c = beam.ray_at(w).at(t);
    let size = match rng.random_range(0..4) {
        0 => uniform(rng, 0.5, 3.0) * (1.0 + t),
        _ => uniform(rng, 0.005, 0.3) * (1.0 + 0.3 * t),
    };
    let r = rotation(rng);
    let v = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(-0.5, 0.8, 0.0), Vec3::new(-0.4, -0.9, uniform(rng, -0.5, 0.5))];
    Triangle { v: v.map(|p| c + r * (p * size * Vec3::new(uniform(rng, 0.5, 1.5), uniform(rng, 0.5, 1.5), 1.0))) }
}

/// Uniform barycentric coordinates in a triangle.
pub fn barycentric(rng: &mut Rng64) -> Vec3 {
    let (mut a, mut b) = (rng.random::<f32>(), rng.random::<f32>());
    if a + b > 1.0 {
        a = 1.0 - a;
        b = 1.0 - b;
    }
    Vec3::new(a, b, 1.0 - a - b)
}

/// Barycentric grid points `(i/n, j/n, k/n)` with `i + j + k = n`.
pub fn barycentric_grid(n: usize) -> impl Iterator<Item = Vec3> {
    (0..=n).flat_map(move |i| (0..=n - i).map(move |j| Vec3::new(i as f32, j as f32, (n - i - j) as f32) / n as f32))
}
