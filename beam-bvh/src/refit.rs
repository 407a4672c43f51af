//! Refit: recompute every box after the triangles moved, keeping the topology.

use crate::FlatBvh;
use beam_math::{Aabb, Triangle};

impl FlatBvh {
    /// Recompute node boxes bottom-up for moved `triangles` (same count and order as at build).
    /// Children follow their parents in the depth-first layout, so one reverse pass suffices. The
    /// tree keeps its triangles: one left out as degenerate at build stays out; rebuild to add it.
    pub fn refit(&mut self, triangles: &[Triangle]) {
        for i in (0..self.nodes.len()).rev() {
            let n = self.nodes[i];
            let b = if n.is_leaf() {
                let first = n.right_or_first as usize;
                self.prims[first..first + n.count as usize].iter().fold(Aabb::EMPTY, |b, &p| {
                    let t = &triangles[p as usize];
                    b.grow(t.v[0]).grow(t.v[1]).grow(t.v[2])
                })
            } else {
                self.nodes[i + 1].bounds().union(self.nodes[n.right_or_first as usize].bounds())
            };
            self.nodes[i].min = b.min.to_array();
            self.nodes[i].max = b.max.to_array();
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{BuildOptions, FlatBvh};
    use beam_math::glam::Vec3;
    use beam_math::{Ray, Triangle};

    #[test]
    fn refit_follows_moved_triangles() {
        let mut tris: Vec<Triangle> = (0..200)
            .map(|i| {
                let o = Vec3::new(i as f32, 0.0, 0.0);
                Triangle::new(o, o + Vec3::X, o + Vec3::Y)
            })
            .collect();
        let mut bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        for t in &mut tris {
            for v in &mut t.v {
                v.z += 5.0 + v.x * 0.1;
            }
        }
        bvh.refit(&tris);
        let ray = Ray::new(Vec3::new(100.3, 0.3, -1.0), Vec3::Z);
        let hit = bvh.closest_hit(&tris, ray, f32::INFINITY).expect("moved triangle is found");
        assert_eq!(hit.prim, 100);
    }
}
