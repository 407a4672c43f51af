//! The GPU ray tracer against the CPU's BVH traversal on built-in scenes: camera rays and random
//! rays through the scene's box, closest and any hits. Skipped, with the reason printed, only when
//! no GPU adapter exists at all (CI installs Mesa's lavapipe, so it runs there).

use beam_bvh::gpu::GpuBvh;
use beam_gpu::Gpu;
use beam_gpu::raytrace::{GpuHit, GpuRay, RayTracer};
use beam_math::Ray;
use beam_math::glam::Vec3;
use rand::{Rng, SeedableRng};

#[test]
fn gpu_hits_equal_cpu_hits() {
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            println!("skipped: {e}");
            return;
        }
    };
    println!("adapter: {}", gpu.describe());
    let mut rng = rand_pcg::Pcg32::seed_from_u64(7);
    for name in ["cornell", "mirror-glass", "wavy-lake"] {
        let scene = beam_cpu::scene::builtin(name).unwrap();
        let tracer = RayTracer::new(&gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)).unwrap();
        let bounds = scene.bounds();
        let camera = scene.camera.with_size(128, 128);
        let frame = camera.frame();
        let mut rays: Vec<_> = (0..128 * 128).map(|i| (camera.pixel_ray(&frame, i), f32::INFINITY, 0)).collect();
        for k in 0..20_000 {
            let p = |rng: &mut rand_pcg::Pcg32| {
                bounds.min + (bounds.max - bounds.min) * Vec3::new(rng.random(), rng.random(), rng.random())
            };
            let (a, b) = (p(&mut rng), p(&mut rng));
            rays.push((Ray::new(a, b - a), if k % 2 == 0 { f32::INFINITY } else { 1.0 }, (k % 2) as u32));
        }
        let gpu_rays: Vec<GpuRay> = rays
            .iter()
            .map(|&(r, t_max, kind)| GpuRay {
                origin: r.origin.to_array(),
                t_max: t_max.min(3.0e38),
                direction: r.direction.to_array(),
                kind,
            })
            .collect();
        let hits = tracer.trace(&gpu, &gpu_rays).unwrap();
        let (mut mismatches, mut worst) = (0usize, 0.0f32);
        for (&(ray, t_max, kind), hit) in rays.iter().zip(&hits) {
            if kind == 1 {
                let cpu = scene.bvh.any_hit(&scene.triangles, ray, t_max);
                if cpu != (hit.t > 0.5) {
                    mismatches += 1;
                }
                continue;
            }
            match (scene.bvh.closest_hit(&scene.triangles, ray, t_max), hit.prim) {
                (None, GpuHit::MISS) => {}
                (Some(c), p) if p == c.prim => worst = worst.max((c.t - hit.t).abs() / c.t.max(1.0)),
                // Ties: another triangle at the same distance (shared edges, coplanar faces).
                (Some(c), p) if p != GpuHit::MISS && (c.t - hit.t).abs() <= 1e-5 * c.t.max(1.0) => {}
                _ => mismatches += 1,
            }
        }
        println!("{name}: {} rays, {mismatches} mismatches, worst relative Δt {worst:.1e}", rays.len());
        // Rays exactly on an edge may be decided differently (the CPU refines in f64): at most 1 in 10⁴.
        assert!(mismatches * 10_000 <= rays.len(), "{name}: {mismatches} mismatches of {}", rays.len());
        assert!(worst <= 1e-5, "{name}: Δt {worst}");
    }
}
