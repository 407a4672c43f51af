//! The GPU's nonlinear path on a coarse S mesh (000 §7.1): beams spawned by simplified faces that
//! stand for many fine triangles, rasterized by the GPU's atlases (which must skip the fine patch
//! under each face and take its ring's near hits for self-hits, as the CPU does), composited on the
//! GPU where the CPU looks each point's child beams up ([`Composite::reflected_at`] and
//! `refracted_at`, looked up on the GPU too, `lib/coarse.wgsl`), against the CPU renderer with the
//! same S mesh.
//!
//! [`Composite::reflected_at`]: beam_render::nonlinear::Composite

use super::device::adapter;
use super::pixels::PixelDifference;
use super::twin::TwinShading;
use crate::property::{Backend, Config, Outcome};
use beam_cpu::nonlinear::CpuBeams;
use beam_gpu::nonlinear::GpuBeams;
use beam_math::Triangle;
use beam_math::collide::closest_point_on_triangle;
use beam_render::nonlinear::SMesh;
use beam_render::nonlinear::{Degree, EyeView};
use beam_render::nonlinear::{NonlinearOptions, render_nonlinear_with};
use beam_render::options::RenderOptions;
use beam_scene::scene::{self, Simplify};

/// Image side: small, for lavapipe.
const SIZE: u32 = 64;
/// Faces of the simplified S mesh over the teapot and the glass ball (about 6,800 fine triangles).
const FACES: u32 = 400;

/// The mirror teapot with its specular surfaces' S mesh simplified to about [`FACES`] faces.
fn coarse_teapot() -> Result<scene::Scene, String> {
    let mut scene = scene::builtin("mirror-teapot").map_err(|e| e.to_string())?;
    scene.smesh.rest = Some(Simplify::Faces(FACES));
    Ok(scene)
}

/// The mirror teapot (a mirror teapot and a glass ball) at 64² with its specular surfaces' S mesh
/// simplified to about 400 faces, S1 and S3, two tree levels, area-light caustics off (they are
/// traced on the fine mesh either way): the GPU's image (its ray tracer, atlases, shading and
/// composite) against the CPU renderer's with the GPU's shading estimator (`TwinShading`). At most
/// 0.5% of the pixels may differ by more than 4/255 in a channel (sRGB), as for the fine S meshes
/// of `gpu_images_equal_cpu`; both renders must use the coarse faces (beams off them, not rays
/// alone), the GPU's must look points up on the GPU, and the beam counts must agree within 2%.
/// The mean error and the points under coarse faces traced by rays are stated.
pub(super) fn gpu_coarse_smesh_equals_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let scene = coarse_teapot()?;
    let (mut pixels, mut notes) = (0u64, Vec::new());
    for degree in [Degree::S1, Degree::S3] {
        let options = NonlinearOptions {
            degree,
            texels: 16,
            bounces: 2,
            caustic_strata: 0,
            shading: RenderOptions::exact(SIZE, SIZE),
        };
        let mut renderer = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let (on_gpu, gpu_stats) =
            render_nonlinear_with(&scene, &options, &mut renderer, &CpuBeams).map_err(|e| e.to_string())?;
        let (on_cpu, cpu_stats) = render_nonlinear_with(&scene, &options, &mut TwinShading::default(), &CpuBeams)
            .map_err(|e| e.to_string())?;
        let name = format!("{degree:?}");
        if cpu_stats.coarse_smesh_faces == 0 || cpu_stats.coarse_smesh_faces > u64::from(2 * FACES) {
            return Err(format!("{name}: {} coarse S-mesh faces, not about {FACES}", cpu_stats.coarse_smesh_faces));
        }
        let beams = |s: &beam_render::nonlinear::NonlinearStats| s.beams_per_level.iter().sum::<u64>();
        let (g, c) = (beams(&gpu_stats), beams(&cpu_stats));
        if c == 0 || g.abs_diff(c) * 50 > c {
            return Err(format!("{name}: {g} beams on the GPU, {c} on the CPU"));
        }
        let PixelDifference { differ, sum, n } = PixelDifference::of(&on_gpu, &on_cpu);
        if differ * 200 > n {
            return Err(format!(
                "{name}: {differ} of {n} pixels differ by more than 4/255 (mean {:.2}/255)",
                255.0 * sum / n as f64
            ));
        }
        // The points under coarse faces (the eye's and the first level's) look their child
        // beams up on the GPU, where their composite records are made (`lib/coarse.wgsl`).
        let composited = renderer.times().coarse_records;
        if composited == 0 {
            return Err(format!("{name}: no point under a coarse face was composited on the GPU"));
        }
        pixels += n;
        notes.push(format!(
            "{name}: {} faces, {g} / {c} beams (GPU / CPU), {composited} points composited on the GPU, {:.2}% \
             differ (mean {:.2}/255), by rays {} / {}",
            cpu_stats.coarse_smesh_faces,
            100.0 * differ as f64 / n as f64,
            255.0 * sum / n as f64,
            gpu_stats.uncovered_by_beams,
            cpu_stats.uncovered_by_beams,
        ));
    }
    Ok(Outcome { cases: pixels, note: notes.join("; ") })
}

/// The eye's view on the GPU locates the mirror and glass hits under the coarse faces
/// (`eye.wgsl`'s `nearest_face`) as the host would (`SMesh::locate`): on the mirror teapot at
/// 128×96 with 400 coarse faces, it keeps every such hit (none handed back) and counts it at its
/// face, and per face the counts equal the host's locate of the same hits (read back), but for
/// ties: hits whose nearest candidates lie within 1e-6 of the scene's size of each other (rounded
/// otherwise in f32 on the GPU) may count at either. Some hits must lie on triangles with several
/// candidates (else the GPU chose nothing).
pub(super) fn gpu_eye_locates_as_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let scene = coarse_teapot()?;
    let smesh = SMesh::of(&scene);
    let (width, height) = (128, 96);
    let camera = scene.camera.with_size(width, height);
    let renderer = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
    let eye = renderer.eye_faces(&scene, &smesh, &camera, &RenderOptions::exact(width, height));
    let (eye, mut frame) = eye.map_err(|e| e.to_string())?;
    if let Some((i, _, hit)) = eye.hits.iter().find(|(_, _, h)| !smesh.candidates(h.prim).is_empty()) {
        return Err(format!("pixel {i}: handed back, though triangle {} has S-mesh faces", hit.prim));
    }
    let kept = renderer.take_kept_eye_hits(&scene, &mut frame).map_err(|e| e.to_string())?;
    if kept.len() as u64 != eye.kept {
        return Err(format!("{} kept hits read back, {} counted", kept.len(), eye.kept));
    }
    let extent = scene.bounds().extent().length();
    let distance = |f: u32, p| closest_point_on_triangle(p, &Triangle { v: smesh.faces[f as usize].v }).distance(p);
    let (mut several, mut ties) = (0u64, 0u64);
    let mut on_host = vec![0u64; smesh.faces.len()];
    for &(i, ray, hit) in &kept {
        let p = ray.at(hit.t);
        let Some((face, _)) = smesh.locate(hit.prim, p) else {
            return Err(format!("pixel {i}: kept, but the host locates no face"));
        };
        on_host[face] += 1;
        let candidates = smesh.candidates(hit.prim);
        several += u64::from(candidates.len() > 1);
        let nearest = distance(face as u32, p);
        ties += u64::from(candidates.iter().any(|&g| g as usize != face && distance(g, p) <= nearest + 1e-6 * extent));
    }
    let differ: u64 = on_host.iter().zip(&eye.seen).map(|(&h, g)| h.abs_diff(u64::from(g[0]))).sum();
    if differ > 2 * ties {
        return Err(format!("per-face counts differ by {differ} in all, with {ties} ties"));
    }
    if several == 0 {
        return Err("no hit kept on a triangle with several candidate faces".into());
    }
    Ok(Outcome {
        cases: kept.len() as u64,
        note: format!(
            "{} hits located, {several} among several faces, {ties} ties, counts differ by {differ}",
            kept.len()
        ),
    })
}
