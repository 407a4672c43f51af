//! Shaft and view tests against a scene's cut-out triangles (`alphaMode` `MASK` and `BLEND`,
//! [`AlphaCut`]), in the BVH of their own the scene keeps. A beam cannot split a light exactly at a
//! texture's alpha, so exactness survives this way:
//! - a shadow beam first asks whether a cut-out triangle may hide part of its light (the shaft test
//!   of [`super::shaft`], from the box of its cluster of shade points, once a cluster); where one
//!   may, the light is sampled by shadow rays, which see through the cut-outs ([`Scene::occluded`]),
//!   and counted (`cut_out_beams`); a constant sky, by the ray method's cosine-weighted rays;
//! - an eye-beam region whose view meets a cut-out (even one hidden behind something) goes to
//!   primary rays before its beam is traced (`cut_out_regions`).
//!
//! Everywhere else the beams are exact.
//!
//! [`AlphaCut`]: beam_scene::scene::surface::AlphaCut

use super::eye_regions::Region;
use super::shaft::{Shaft, meets_any};
use beam_bvh::{Control, FlatBvh, NodeVisitor};
use beam_math::collide::aabb_outside_planes;
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};
use beam_scene::scene::{Camera, Scene};

/// The cut-out triangles of a scene and their BVH ([`Scene::cut_out_triangles`]).
#[derive(Clone, Copy)]
pub(crate) struct CutOuts<'a> {
    triangles: &'a [Triangle],
    bvh: &'a FlatBvh,
}

impl<'a> CutOuts<'a> {
    /// The cut-out triangles of `scene`; `None` when it has none.
    pub(crate) fn of(scene: &'a Scene) -> Option<Self> {
        scene.cut_out_triangles().map(|c| Self { triangles: &c.triangles, bvh: &c.bvh })
    }

    /// Whether a cut-out triangle may hide part of the light `polygon` (normal `light_normal`,
    /// towards the lit side) from a point of `points`: false means no segment from the box to the
    /// light meets one.
    pub(crate) fn may_hide(&self, points: &Aabb, polygon: &[Vec3], light_normal: Vec3) -> bool {
        meets_any(self.bvh, self.triangles, &Shaft::new(points, polygon, light_normal)).0
    }

    /// Whether a cut-out triangle may lie in the view of `region` of `camera`'s image: false means
    /// none meets the pyramid of its four corner rays, so its eye beam sees none (a region that
    /// may see one goes to rays before its beam is traced).
    pub(crate) fn may_show(&self, camera: &Camera, region: Region) -> bool {
        let frame = camera.frame();
        let (x0, y0, x1, y1) = (region.x0 as f32, region.y0 as f32, region.x1 as f32, region.y1 as f32);
        let d = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)].map(|(x, y)| camera.ray(&frame, x, y).direction);
        let centre = d.iter().sum::<Vec3>();
        // The side planes through the eye, normals pointing out of the pyramid.
        let planes = core::array::from_fn(|i| {
            let n = d[i].cross(d[(i + 1) % 4]);
            let n = if n.dot(centre) > 0.0 { -n } else { n };
            (n, n.dot(camera.position))
        });
        let mut visit = InView { planes, triangles: self.triangles, found: false };
        self.bvh.traverse(&mut visit);
        visit.found
    }
}

/// Looks for a triangle not wholly outside one of four planes, stopping at the first.
struct InView<'a> {
    planes: [(Vec3, f32); 4],
    triangles: &'a [Triangle],
    found: bool,
}

impl NodeVisitor for InView<'_> {
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        (!aabb_outside_planes(bounds, &self.planes)).then_some(0.0)
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        self.found = prims.iter().any(|&p| {
            let t = &self.triangles[p as usize];
            !self.planes.iter().any(|&(n, d)| t.v.iter().all(|v| n.dot(*v) > d))
        });
        if self.found { Control::Stop } else { Control::Continue }
    }
}
