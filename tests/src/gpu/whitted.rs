//! Whitted rays traced on the GPU (beam-gpu's `GpuWhitted`, depth first and in waves) against the
//! CPU's waves.

use super::device::adapter;
use crate::property::{Backend, Config, Outcome};
use beam_bvh::gpu::GpuBvh;
use beam_cpu::nonlinear::CpuBeams;
use beam_gpu::buffers::{checked, output, read_all};
use beam_gpu::nonlinear::{GpuWhitted, RestJob, RestPoints};
use beam_gpu::raytrace::RayTracer;
use beam_gpu::shade::twin::shade_twin;
use beam_gpu::shade::{PointShader, ShadeInput};
use beam_math::glam::Vec3;
use beam_render::nonlinear::{ShadePoint, shade_by_waves};
use beam_scene::scene;
use rayon::prelude::*;

/// The radiance of every point the eye sees (72², seeded by its pixel) by `GpuWhitted` (mirror,
/// glass and thin-pane points followed by Whitted rays on the GPU, each point's paths depth first
/// in one dispatch and, again, in a dispatch per bounce, every end shaded by the
/// GPU's shading pass with 16 rays per area light) against `shade_by_waves` on the CPU with the
/// shading pass's twin, on five built-ins with tinted, bump-mapped and curved (Phong-normal)
/// mirrors, glass (Fresnel, total internal reflection) and stained glass; on every second scene the
/// points go as two jobs of one call, into two buffers, the second from its fourth element. Per
/// channel within 1e-4 relative + 1e-5; at most 0.5% of the points may differ (a path whose
/// rounding sends it past an edge, or a shadow ray that grazes one). The worst relative error is
/// stated.
pub(super) fn gpu_whitted_equals_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (size, spp) = (72, 16);
    let (mut total, mut notes) = (0u64, Vec::new());
    let names = ["mirror-glass", "bumpy-mirror", "glass-lens-coarse", "facing-mirrors-coarse", "stained-glass"];
    for (s, name) in names.into_iter().enumerate() {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let camera = scene.camera.with_size(size, size);
        let frame = camera.frame();
        let points: Vec<ShadePoint> = (0..(size * size) as usize)
            .filter_map(|i| {
                let ray = camera.pixel_ray(&frame, i);
                let hit = scene.wide.closest_hit(ray, f32::INFINITY)?;
                Some(ShadePoint { prim: hit.prim, p: ray.at(hit.t), d: ray.direction.normalize(), seed: i as u64 })
            })
            .collect();
        let specular = points.iter().filter(|s| !PointShader::shades(&scene, s.prim)).count();
        let twin = |batch: &[ShadePoint]| Ok(batch.par_iter().map(|s| shade_twin(&scene, None, spp, s)).collect());
        let want = shade_by_waves(&scene, &CpuBeams, &twin, &points).map_err(|e| e.to_string())?;
        let mut shader = PointShader::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let tracer = RayTracer::new(&gpu, &GpuBvh::new(&scene.bvh, &scene.triangles).map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())?;
        let bytes = (points.len() * 16) as u64;
        let inputs: Vec<ShadeInput> = points.iter().map(ShadeInput::new).collect();
        // Alternately in one job, and in two whose waves go together: the first third into a
        // buffer of its own, the rest three elements into another.
        let split = inputs.len() / 3;
        // Each point's paths followed depth first in one dispatch, then in waves.
        let depth_first = GpuWhitted::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let waves = GpuWhitted::new(&gpu, &scene).map_err(|e| e.to_string())?.in_waves();
        for (whitted, how) in [(depth_first, "depth first"), (waves, "in waves")] {
            let got: Vec<[f32; 4]> = checked(&gpu, || {
                let prepared = shader.prepare(&gpu, None);
                let shading = (&shader, &prepared, spp);
                if s % 2 == 0 {
                    let radiance = output(&gpu, "radiance", bytes);
                    let job = RestJob { points: RestPoints::Host(&inputs), radiance: &radiance, first: 0 };
                    whitted.shade_into(&gpu, &tracer, shading, &[job], None)?;
                    return read_all(&gpu, Vec::new(), std::iter::once((&radiance, bytes)));
                }
                let (a, b) = inputs.split_at(split);
                let bytes_of = |n: usize| (n * 16) as u64;
                // Its shadings checked once, at the end (into new buffers where shaded again).
                let radiance = shader.shade_checked(&gpu, |checks| {
                    let radiance =
                        (output(&gpu, "radiance", bytes_of(a.len())), output(&gpu, "radiance", bytes_of(b.len() + 3)));
                    let jobs = [
                        RestJob { points: RestPoints::Host(a), radiance: &radiance.0, first: 0 },
                        RestJob { points: RestPoints::Host(b), radiance: &radiance.1, first: 3 },
                    ];
                    whitted.shade_into(&gpu, &tracer, shading, &jobs, Some(checks))?;
                    Ok(radiance)
                })?;
                let mut out: Vec<[f32; 4]> =
                    read_all(&gpu, Vec::new(), std::iter::once((&radiance.0, bytes_of(a.len()))))?;
                let rest: Vec<[f32; 4]> =
                    read_all(&gpu, Vec::new(), std::iter::once((&radiance.1, bytes_of(b.len() + 3))))?;
                if rest[..3] != [[0.0; 4]; 3] {
                    return Err(beam_gpu::GpuError::Internal("radiance added before a job's first element"));
                }
                out.extend_from_slice(&rest[3..]);
                Ok(out)
            })
            .map_err(|e| e.to_string())?;
            let (mut differ, mut worst) = (0u64, 0.0f32);
            for (g, c) in got.iter().zip(&want) {
                let g = Vec3::new(g[0], g[1], g[2]);
                let error = (g - *c).abs();
                if error.cmpgt(1e-4 * c.abs() + Vec3::splat(1e-5)).any() {
                    differ += 1;
                } else {
                    worst = worst.max((error / (c.abs() + Vec3::splat(1e-2))).max_element());
                }
            }
            let n = points.len() as u64;
            if got.len() as u64 != n || differ * 200 > n || specular == 0 {
                return Err(format!("{name} {how}: {differ} of {n} points differ ({specular} specular)"));
            }
            total += n;
            notes.push(format!("{name} {how}: {specular} of {n} specular, {differ} differ, worst {worst:.1e}"));
        }
    }
    Ok(Outcome { cases: total, note: format!("{} ({})", notes.join("; "), gpu.describe()) })
}
