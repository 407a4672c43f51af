//! The eye's view made and traced on the GPU (beam-gpu's `GpuEye`) against the CPU's.

use super::device::adapter;
use crate::property::{Backend, Config, Outcome};
use beam_cpu::nonlinear::CpuBeams;
use beam_gpu::nonlinear::GpuBeams;
use beam_gpu::shade::PointShader;
use beam_math::glam::Vec3;
use beam_render::nonlinear::EyeView;
use beam_render::options::RenderOptions;
use beam_scene::region::PixelRect;
use beam_scene::scene;

/// `GpuBeams::eye_view` against `CpuBeams`' (the primary ray of every pixel centre, its nearest hit)
/// on four built-ins at 96×80, for one of them with a region: every mirror and glass hit of the
/// frame is returned, every diffuse, glossy and emissive hit of the region kept on the GPU (and
/// handed back by `take_kept_eye`, seeded by its pixel), no other. Per pixel the same triangle, or
/// another at the same distance (a shared edge), with the hit point within 1e-5 of the scene's
/// size; at most 0.1% of the pixels may differ.
pub(super) fn gpu_eye_view_equals_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (width, height) = (96, 80);
    let (mut total, mut notes) = (0u64, Vec::new());
    let corner = PixelRect { x0: 17, y0: 9, x1: 70, y1: 61 };
    for (name, region) in [("cornell", None), ("mirror-glass", None), ("glass-lens", None), ("wavy-lake", Some(corner))]
    {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let on_gpu = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let options = RenderOptions { region, ..RenderOptions::exact(width, height) };
        let camera = scene.camera.with_size(width, height);
        let crop = options.region();
        let (frame, extent) = (camera.frame(), scene.bounds().extent().length());
        let (want, _) = CpuBeams.eye_view(&scene, &camera, &options).map_err(|e| e.to_string())?;
        let (got, mut kept_frame) = on_gpu.eye_view(&scene, &camera, &options).map_err(|e| e.to_string())?;
        let kept = on_gpu.take_kept_eye(&mut kept_frame).map_err(|e| e.to_string())?;
        // Per pixel, the GPU's triangle and hit point.
        let mut seen: Vec<Option<(u32, Vec3)>> = vec![None; (width * height) as usize];
        for &(i, ray, hit) in &got {
            if PointShader::shades(&scene, hit.prim) {
                return Err(format!("{name}: pixel {i}'s shaded triangle {} was handed back", hit.prim));
            }
            seen[i] = Some((hit.prim, ray.at(hit.t)));
        }
        let mut worst_d = 0.0f32;
        for t in &kept {
            let i = t.texel as usize;
            let (x, y) = (t.texel % width, t.texel / width);
            let direction = camera.pixel_ray(&frame, i).direction.normalize();
            worst_d = worst_d.max((t.point.d - direction).length());
            if !PointShader::shades(&scene, t.point.prim) || !crop.contains(x, y) || t.point.seed != u64::from(t.texel)
            {
                return Err(format!("{name}: pixel {i} kept with triangle {}, seed {}", t.point.prim, t.point.seed));
            }
            if seen[i].replace((t.point.prim, t.point.p)).is_some() {
                return Err(format!("{name}: pixel {i} twice"));
            }
        }
        let (mut mismatches, mut worst_p, mut expected) = (0usize, 0.0f32, 0usize);
        for &(i, ray, hit) in &want {
            let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
            if PointShader::shades(&scene, hit.prim) && !crop.contains(x, y) {
                continue;
            }
            expected += 1;
            let p = ray.at(hit.t);
            match seen[i].take() {
                Some((prim, q)) if prim == hit.prim => worst_p = worst_p.max((q - p).length() / extent),
                // Ties: another triangle at the same distance (shared edges, coplanar faces).
                Some((_, q)) if (q - p).length() <= 1e-5 * extent => {}
                _ => mismatches += 1,
            }
        }
        // Pixels the GPU hit and the CPU did not.
        mismatches += seen.iter().flatten().count();
        let n = (width * height) as usize;
        if mismatches * 1000 > n || worst_p > 1e-5 || worst_d > 1e-5 {
            return Err(format!(
                "{name}: {mismatches} of {n} pixels differ, hit points up to {worst_p:.1e}, directions {worst_d:.1e}"
            ));
        }
        total += n as u64;
        notes.push(format!(
            "{name}: {} kept, {} handed back of {expected}, {mismatches} differ, Δp ≤ {worst_p:.1e}",
            kept.len(),
            got.len()
        ));
    }
    Ok(Outcome { cases: total, note: format!("{} ({})", notes.join("; "), gpu.describe()) })
}
