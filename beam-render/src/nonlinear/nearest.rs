//! The triangle of a set nearest a point, through a BVH over the set: how coarse S meshes map the
//! fine mesh's points to their faces and their vertices to the fine mesh's normals (000 §7.1).

use beam_bvh::{BuildOptions, Control, FlatBvh, NodeVisitor};
use beam_math::collide::closest_point_on_triangle;
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};

/// A set of triangles for nearest-point queries.
pub(super) struct Nearest<'a> {
    triangles: &'a [Triangle],
    bvh: FlatBvh,
}

impl<'a> Nearest<'a> {
    /// The BVH over `triangles` (degenerate ones are never nearest).
    pub(super) fn new(triangles: &'a [Triangle]) -> Self {
        Self { triangles, bvh: FlatBvh::build(triangles, &BuildOptions::sah()) }
    }

    /// The index of the triangle nearest `p` and its point nearest `p`; `None` for an empty set or
    /// a point that is not finite.
    pub(super) fn query(&self, p: Vec3) -> Option<(u32, Vec3)> {
        self.query_facing(p, Vec3::ZERO)
    }

    /// [`Self::query`] among the triangles whose normal is within 90° of `facing` (all of them
    /// for a zero `facing`): the surface a point lies on, not the far side of a thin one.
    pub(super) fn query_facing(&self, p: Vec3, facing: Vec3) -> Option<(u32, Vec3)> {
        if !p.is_finite() {
            return None;
        }
        let mut v = Visit { p, facing, triangles: self.triangles, best: f32::INFINITY, found: None };
        self.bvh.traverse(&mut v);
        v.found
    }
}

/// Branch and bound: boxes nearer than the best triangle so far, nearest first.
struct Visit<'a> {
    p: Vec3,
    facing: Vec3,
    triangles: &'a [Triangle],
    /// Squared distance of the best triangle so far.
    best: f32,
    found: Option<(u32, Vec3)>,
}

impl NodeVisitor for Visit<'_> {
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        let d2 = (self.p.clamp(bounds.min, bounds.max) - self.p).length_squared();
        (d2 <= self.best).then_some(d2)
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        for &i in prims {
            let tri = &self.triangles[i as usize];
            if tri.scaled_normal().dot(self.facing) < 0.0 {
                continue;
            }
            let q = closest_point_on_triangle(self.p, tri);
            let d2 = (q - self.p).length_squared();
            if d2 < self.best {
                (self.best, self.found) = (d2, Some((i, q)));
            }
        }
        Control::Continue
    }

    fn cutoff(&self) -> f32 {
        self.best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_brute_force_nearest() {
        let tris: Vec<Triangle> = (0..200)
            .map(|i| {
                let c = Vec3::new((i % 10) as f32, (i / 10 % 5) as f32 * 1.3, (i / 50) as f32 * 0.7);
                Triangle { v: [c, c + Vec3::new(0.4, 0.1, 0.0), c + Vec3::new(0.0, 0.3, 0.2)] }
            })
            .collect();
        let near = Nearest::new(&tris);
        for k in 0..100 {
            let p = Vec3::new((k * 37 % 101) as f32 / 9.0, (k * 13 % 53) as f32 / 7.0, (k % 7) as f32 / 2.0 - 1.0);
            let (i, q) = near.query(p).unwrap();
            let brute = tris.iter().map(|t| closest_point_on_triangle(p, t).distance(p)).fold(f32::INFINITY, f32::min);
            assert!((q.distance(p) - brute).abs() < 1e-5, "{i}");
        }
        assert!(near.query(Vec3::NAN).is_none());
        // Every triangle's normal is (0.02, -0.08, 0.12): none faces -z, all face +z.
        assert!(near.query_facing(Vec3::ZERO, Vec3::NEG_Z).is_none());
        assert_eq!(near.query_facing(Vec3::ONE, Vec3::Z), near.query(Vec3::ONE));
        assert!(Nearest::new(&[]).query(Vec3::ZERO).is_none());
    }
}
