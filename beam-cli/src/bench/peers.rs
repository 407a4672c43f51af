//! Benchmark peers behind the `peers` feature: Embree 3 and obvhs (CWBVH).
//!
//! tinybvh is not among them: tinybvh-rs 0.1.0-beta.3 returns a BVH whose C++ object pointer is
//! null after building any real mesh here (the 6,320-triangle teapot already; synthetic meshes of
//! 8,000 triangles work), so every query panics.

use super::Tracer;
use beam_math::{Ray, Triangle};
use std::time::Instant;

/// Every peer, built over `triangles` (degenerate ones already removed by the caller).
pub fn all(triangles: &[Triangle]) -> Result<Vec<Box<dyn Tracer>>, String> {
    Ok(vec![Box::new(Embree::new(triangles)?), Box::new(Obvhs::new(triangles))])
}

/// Embree's any-hit query over `triangles`, as a shadow-ray tracer for the renderer.
pub fn embree_occluder(triangles: &[Triangle]) -> Result<Box<beam_scene::queries::AnyHit<'static>>, String> {
    let e = Embree::new(triangles)?;
    Ok(Box::new(move |ray: Ray, t_max: f32| e.occluded(&ray, t_max)))
}

/// Embree's closest hit over `triangles`: the index of the triangle hit and the ray parameter.
pub fn embree_closest(triangles: &[Triangle]) -> Result<Box<beam_scene::queries::ClosestHit<'static>>, String> {
    let e = Embree::new(triangles)?;
    Ok(Box::new(move |ray: Ray| e.closest_prim(&ray)))
}

/// Embree 3.13 through the `embree3` crate: default (medium) build quality, all threads.
struct Embree {
    scene: embree3::Scene<'static>,
    build_ms: f64,
}

impl Embree {
    fn new(triangles: &[Triangle]) -> Result<Self, String> {
        use embree3::{BufferUsage, Device, Format, GeometryKind};
        let device = Device::new().map_err(|e| format!("embree: {e:?}"))?;
        let mut scene = device.create_scene().map_err(|e| format!("embree: {e:?}"))?;
        let start = Instant::now();
        let mut geom = device.create_geometry(GeometryKind::TRIANGLE).map_err(|e| format!("embree: {e:?}"))?;
        let n = triangles.len();
        geom.set_new_buffer::<[f32; 3]>(BufferUsage::VERTEX, 0, Format::FLOAT3, 12, 3 * n)
            .map_err(|e| format!("embree: {e:?}"))?
            .copy_from_slice(&triangles.iter().flat_map(|t| t.v.map(|v| v.to_array())).collect::<Vec<_>>());
        geom.set_new_buffer::<[u32; 3]>(BufferUsage::INDEX, 0, Format::UINT3, 12, n)
            .map_err(|e| format!("embree: {e:?}"))?
            .copy_from_slice(&(0..n as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect::<Vec<_>>());
        let geom = geom.commit();
        scene.attach_geometry(&geom);
        scene.commit();
        Ok(Self { scene, build_ms: start.elapsed().as_secs_f64() * 1e3 })
    }

    /// The closest hit's triangle index and ray parameter.
    fn closest_prim(&self, ray: &Ray) -> Option<(u32, f32)> {
        let mut ctx = embree3::IntersectContext::incoherent();
        let mut rh = embree3::RayHit::from(embree3::Ray::segment(
            ray.origin.to_array(),
            ray.direction.to_array(),
            0.0,
            f32::INFINITY,
        ));
        self.scene.intersect(&mut ctx, &mut rh);
        rh.hit.is_valid().then_some((rh.hit.primID, rh.ray.tfar))
    }
}

impl Tracer for Embree {
    fn name(&self) -> String {
        "embree3".into()
    }
    fn build_ms(&self) -> f64 {
        self.build_ms
    }
    fn closest(&self, ray: &Ray) -> Option<f32> {
        self.closest_prim(ray).map(|(_, t)| t)
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let mut ctx = embree3::IntersectContext::incoherent();
        let mut r = embree3::Ray::segment(ray.origin.to_array(), ray.direction.to_array(), 0.0, t_max);
        self.scene.occluded(&mut ctx, &mut r)
    }
}

/// obvhs 0.4: its CWBVH (compressed 8-wide) from the medium-quality PLOC build, parallel.
struct Obvhs {
    bvh: obvhs::cwbvh::CwBvh,
    tris: Vec<obvhs::triangle::Triangle>,
    build_ms: f64,
}

impl Obvhs {
    fn new(triangles: &[Triangle]) -> Self {
        use glam034::Vec3A;
        let tris: Vec<obvhs::triangle::Triangle> = triangles
            .iter()
            .map(|t| obvhs::triangle::Triangle {
                v0: Vec3A::from_array(t.v[0].to_array()),
                v1: Vec3A::from_array(t.v[1].to_array()),
                v2: Vec3A::from_array(t.v[2].to_array()),
            })
            .collect();
        let start = Instant::now();
        let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &tris,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        Self { bvh, tris, build_ms: start.elapsed().as_secs_f64() * 1e3 }
    }

    fn ray(ray: &Ray, t_max: f32) -> obvhs::ray::Ray {
        use glam034::Vec3A;
        obvhs::ray::Ray::new(
            Vec3A::from_array(ray.origin.to_array()),
            Vec3A::from_array(ray.direction.to_array()),
            0.0,
            t_max,
        )
    }
}

impl Tracer for Obvhs {
    fn name(&self) -> String {
        "obvhs-cwbvh".into()
    }
    fn build_ms(&self) -> f64 {
        self.build_ms
    }
    fn closest(&self, ray: &Ray) -> Option<f32> {
        let mut hit = obvhs::ray::RayHit::none();
        let r = Self::ray(ray, f32::INFINITY);
        let found =
            self.bvh.ray_traverse(r, &mut hit, |r, id| self.tris[self.bvh.primitive_indices[id] as usize].intersect(r));
        found.then_some(hit.t)
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let mut hit = obvhs::ray::RayHit::none();
        let r = Self::ray(ray, t_max);
        // obvhs has no early-exit any-hit for a plain closure; closest hit clipped at t_max.
        self.bvh.ray_traverse(r, &mut hit, |r, id| self.tris[self.bvh.primitive_indices[id] as usize].intersect(r))
    }
}
