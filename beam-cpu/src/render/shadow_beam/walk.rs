//! A shadow beam's own walk through the BVH, culling nodes by the frustum of its pieces.

use super::ShadowBeam;
use beam_bvh::{Control, FlatBvh, NodeVisitor};
use beam_math::collide::aabb_outside_planes;
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};
use beam_render::tolerance::DEPTH_EPS;

/// Traces a shadow beam through the BVH.
struct ShadowVisitor<'a, 'b, 's> {
    triangles: &'a [Triangle],
    beam: &'b mut ShadowBeam<'s>,
    /// Outward normals of the four planes through the apex and the pieces' bounding rectangle's
    /// sides, then the near and far planes (`depth =` [`ShadowBeam::touch`], where occluders are
    /// looked for, and `depth = 1 − DEPTH_EPS`), as (normal, offset).
    planes: [(Vec3, f32); 6],
}

impl ShadowVisitor<'_, '_, '_> {
    fn update_planes(&mut self) {
        let f = &self.beam.frame;
        let (lo, hi) = self.beam.bounds();
        for (plane, n) in self.planes.iter_mut().zip(f.side_normals(lo, hi)) {
            *plane = (n, n.dot(f.apex));
        }
        // Depth d(x) = (x − apex)·N / distance: near plane keeps d ≥ touch, far plane keeps
        // d ≤ 1 − ε.
        let n = f.normal / f.distance;
        self.planes[4] = (-n, -n.dot(f.apex) - self.beam.touch());
        self.planes[5] = (n, n.dot(f.apex) + 1.0 - DEPTH_EPS);
    }
}

impl NodeVisitor for ShadowVisitor<'_, '_, '_> {
    /// A node is entered unless its box lies wholly outside one of the beam's six planes (the four
    /// through the apex and the sides of the pieces' bounding rectangle, the near and far planes),
    /// tested at the box corner nearest to the inside: the plane test of frustum culling, cheap and
    /// conservative (001 §3.3 keeps near and far planes per axis for the same purpose).
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        self.beam.stats.bvh_steps += 1;
        if aabb_outside_planes(bounds, &self.planes) {
            return None;
        }
        Some(0.0)
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        for &p in prims {
            if self.beam.occlude(&self.triangles[p as usize]) {
                if self.beam.finished() {
                    return Control::Stop;
                }
                // Pieces only shrink where the triangle hit one; otherwise the planes still hold.
                self.update_planes();
            }
        }
        if self.beam.over_budget() { Control::Stop } else { Control::Continue }
    }
}

/// Trace `beam` through the BVH: what is left of it are its lit pieces.
pub(crate) fn trace_bvh(bvh: &FlatBvh, triangles: &[Triangle], beam: &mut ShadowBeam<'_>) {
    let mut v = ShadowVisitor { triangles, beam, planes: [(Vec3::ZERO, 0.0); 6] };
    v.update_planes();
    bvh.traverse(&mut v);
}
