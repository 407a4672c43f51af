//! Bounding-cone culling of the scene for one beam (000 App. A): the triangles a beam may meet.

use super::texture::Exclude;
use crate::scene::Scene;
use beam_bvh::{Control, NodeVisitor};
use beam_math::Aabb;
use beam_math::collide::{Cone, ConeSpheres};

/// The scene triangles that may meet a beam with bounding cone `cone`, less those it skips
/// (`exclude`, the surface under its base): bounding-cone culling (000 App. A) of the BVH's boxes,
/// then of each triangle's bounding sphere.
#[must_use]
pub fn cone_candidates(scene: &Scene, cone: &Cone, exclude: Exclude<'_>) -> Vec<u32> {
    let mut cull = ConeCull { cone: ConeSpheres::new(cone), prims: Vec::new() };
    scene.bvh.traverse(&mut cull);
    cull.prims.retain(|&i| {
        let (centre, radius) = scene.bounding_sphere(i);
        !exclude.skips(i) && cull.cone.meets(centre, radius)
    });
    cull.prims
}

/// Collects the triangles of the BVH leaves whose boxes' bounding spheres meet a beam's bounding
/// cone.
struct ConeCull {
    cone: ConeSpheres,
    prims: Vec<u32>,
}

impl NodeVisitor for ConeCull {
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        self.cone.meets(bounds.center(), 0.5 * bounds.extent().length()).then_some(0.0)
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        self.prims.extend_from_slice(prims);
        Control::Continue
    }
}
