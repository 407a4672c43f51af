//! Benchmark peers behind the `peers` feature: Embree 3, obvhs (CWBVH) and tinybvh.
//!
//! tinybvh through tinybvh-rs 0.1.0-beta.3 (tinybvh 1.6.8): its binary BVH ("Wald" layout) always;
//! its 8-wide CPU layout (`BVH8_CPU`) only when this binary is compiled with AVX2
//! (`RUSTFLAGS="-C target-cpu=native"`), because tinybvh-rs offers that layout's query only then.
//! tinybvh-rs has no any-hit query: shadow rays are closest hits clipped at `t_max`.
//!
//! tinybvh-rs declares tinybvh's `Ray` as 64 bytes; tinybvh 1.6.8's is 128 (aligned to 64, with an
//! `auxData` pointer and a 56-byte user union after the hit). Its `Ray::new` runs the C++
//! constructor, whose `memset(this, 0, sizeof(Ray))` writes 128 bytes into a 64-byte return slot
//! and corrupts the caller's stack (the crash that kept tinybvh out of this benchmark before). The
//! fields the queries use agree (`t` at byte 48, `prim` at 60), so rays are built here field by
//! field, inside a 128-byte buffer, and `Ray::new` is never called.

use super::tracer::Tracer;
use beam_math::{Ray, Triangle};
use std::time::Instant;

/// Every peer, built over `triangles` (degenerate ones already removed by the caller).
pub(super) fn all(triangles: &[Triangle]) -> Result<Vec<Box<dyn Tracer>>, String> {
    let mut out: Vec<Box<dyn Tracer>> = vec![
        Box::new(Embree::timed(triangles, false)?),
        Box::new(Embree::timed(triangles, true)?),
        Box::new(Obvhs::new(triangles)),
    ];
    out.extend(tinybvh::all(triangles)?);
    Ok(out)
}

/// One more build of Embree (`embree3` or `embree3-hq`) over `triangles`, in milliseconds.
pub(super) fn build_ms(name: &str, triangles: &[Triangle]) -> Option<f64> {
    let high_quality = match name {
        "embree3" => false,
        "embree3-hq" => true,
        _ => return None,
    };
    Embree::new(triangles, high_quality).ok().map(|e| e.build_ms)
}

/// Embree's any-hit query over `triangles`, as a shadow-ray tracer for the renderer.
pub(super) fn embree_occluder(triangles: &[Triangle]) -> Result<Box<beam_render::queries::AnyHit<'static>>, String> {
    let e = Embree::new(triangles, false)?;
    Ok(Box::new(move |ray: Ray, t_max: f32| e.occluded(&ray, t_max)))
}

/// Embree's closest hit over `triangles`: the index of the triangle hit and the ray parameter.
pub(super) fn embree_closest(triangles: &[Triangle]) -> Result<Box<beam_render::queries::ClosestHit<'static>>, String> {
    let e = Embree::new(triangles, false)?;
    Ok(Box::new(move |ray: Ray| e.closest_prim(&ray)))
}

/// Embree 3.13 through the `embree3` crate, all threads: default (medium) build quality, or high
/// quality (`RTC_BUILD_QUALITY_HIGH`: Embree's SAH builder with spatial splits), the peer of our
/// [`BuildOptions::high_quality`](beam_bvh::BuildOptions::high_quality). In the BVH benchmark's
/// table its build time is the median of three; its ratio lines build it again with [`build_ms`],
/// in turn with ours.
struct Embree {
    scene: embree3::Scene<'static>,
    build_ms: f64,
    high_quality: bool,
}

impl Embree {
    fn new(triangles: &[Triangle], high_quality: bool) -> Result<Self, String> {
        use embree3::{BufferUsage, BuildQuality, Device, Format, GeometryKind};
        let device = Device::new().map_err(|e| format!("embree: {e:?}"))?;
        let mut scene = device.create_scene().map_err(|e| format!("embree: {e:?}"))?;
        if high_quality {
            scene.set_build_quality(BuildQuality::HIGH);
        }
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
        Ok(Self { scene, build_ms: start.elapsed().as_secs_f64() * 1e3, high_quality })
    }

    /// [`Embree::new`] three times, keeping the last scene and the median build time (as ours are
    /// timed: the first build also pays for starting Embree's threads).
    fn timed(triangles: &[Triangle], high_quality: bool) -> Result<Self, String> {
        let mut runs = Vec::new();
        for _ in 0..3 {
            runs.push(Self::new(triangles, high_quality)?);
        }
        let mut times: Vec<f64> = runs.iter().map(|e| e.build_ms).collect();
        times.sort_by(f64::total_cmp);
        let mut last = runs.pop().ok_or("embree: no build")?;
        last.build_ms = times[1];
        Ok(last)
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
        if self.high_quality { "embree3-hq" } else { "embree3" }.into()
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

mod tinybvh {
    use super::Tracer;
    use beam_math::{Ray, Triangle};
    use std::time::Instant;
    use tinybvh_rs::{Intersector, bvh};

    /// tinybvh's layouts over `triangles`.
    pub(super) fn all(triangles: &[Triangle]) -> Result<Vec<Box<dyn Tracer>>, String> {
        // The binary BVH borrows its vertices for its whole life: leaked, once per run.
        let positions: &'static [[f32; 4]] =
            triangles.iter().flat_map(|t| t.v.map(|v| v.extend(0.0).to_array())).collect::<Vec<_>>().leak();
        let start = Instant::now();
        let wald = bvh::BVH::new(positions.into()).map_err(|e| format!("tinybvh: {e}"))?;
        let build_ms = start.elapsed().as_secs_f64() * 1e3;
        #[allow(unused_mut, reason = "mutated only where the target has AVX2 (the BVH8 layout)")]
        let mut out: Vec<Box<dyn Tracer>> = vec![Box::new(Tiny { name: "tinybvh-wald", bvh: wald, build_ms })];
        #[cfg(target_feature = "avx2")]
        {
            use tinybvh_rs::{bvh8_cpu, mbvh};
            let start = Instant::now();
            let mut binary = bvh::BVH::new(positions.into()).map_err(|e| format!("tinybvh: {e}"))?;
            binary.split_leaves(4);
            let bvh = bvh8_cpu::BVH::new(&mbvh::BVH::new(&binary)).map_err(|e| format!("tinybvh: {e}"))?;
            let build_ms = start.elapsed().as_secs_f64() * 1e3;
            out.push(Box::new(Tiny { name: "tinybvh-bvh8-cpu", bvh, build_ms }));
        }
        Ok(out)
    }

    struct Tiny<B> {
        name: &'static str,
        bvh: B,
        build_ms: f64,
    }

    // SAFETY: the rays of a benchmark are traced from several threads at once, and tinybvh-rs
    // does not mark its C++ objects `Sync`. The only call made on a shared `Tiny` is `Intersect`,
    // a `const` method of tinybvh's `BVH` and `BVH8_CPU` (tiny_bvh.h 1.6.8) that reads the tree and
    // its vertices and writes only the `Ray` it is given; tinybvh keeps no `mutable` members and
    // no shared static state outside its builders (thread-local job systems).
    #[expect(unsafe_code, reason = "tinybvh-rs does not mark its C++ trees Sync; see SAFETY above")]
    unsafe impl<B> Sync for Tiny<B> {}

    /// A ray with room for the 128 bytes tinybvh's `Ray` has (see the module notes).
    #[repr(C, align(64))]
    struct RayBuffer {
        ray: tinybvh_rs::Ray,
        rest: [u8; 64],
    }

    impl<B: Intersector> Tiny<B> {
        fn trace(&self, ray: &Ray, t_max: f32) -> Option<f32> {
            let t_max = t_max.min(tinybvh_rs::INFINITE);
            // What tinybvh's constructor sets, without normalising the direction (so `t` is in
            // the units of ours): mask RAY_MASK_INTERSECT_ALL, instance 0, reciprocal direction.
            let mut buffer = RayBuffer {
                ray: tinybvh_rs::Ray {
                    origin: ray.origin.to_array(),
                    padding_0: 0xFFFF,
                    dir: ray.direction.to_array(),
                    padding_1: 0,
                    r_d: ray.direction.recip().to_array(),
                    padding_2: 0,
                    hit: tinybvh_rs::Intersection { t: t_max, u: 0.0, v: 0.0, prim: 0 },
                },
                rest: [0; 64],
            };
            self.bvh.intersect(&mut buffer.ray);
            (buffer.ray.hit.t < t_max).then_some(buffer.ray.hit.t)
        }
    }

    impl<B: Intersector> Tracer for Tiny<B> {
        fn name(&self) -> String {
            self.name.into()
        }
        fn build_ms(&self) -> f64 {
            self.build_ms
        }
        fn closest(&self, ray: &Ray) -> Option<f32> {
            self.trace(ray, f32::INFINITY)
        }
        fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
            self.trace(ray, t_max).is_some()
        }
    }
}
