//! The GPU's gather of the glossy light volumes (002 §4.3) against the CPU's.

use super::device::adapter;
use crate::property::{Backend, Config, Outcome};
use beam_math::glam::Vec3;
use beam_scene::scene;

/// The WGSL gather of the glossy light volumes (cone hierarchy, specular eq. 1, glossy eq. 3 with
/// Owen's T in f32, second-order shadow rays through the GPU BVH) against the CPU's at 10,000
/// random receiver points of each of the three built-ins of 002: the same shadow masks, and
/// irradiance within 1e-3 relative (+1e-5 of the scene's largest) per channel (the hierarchy walks
/// may differ where f32 puts a point on the other side of a node's cone: counted); at most 0.2% of the points may differ (a flux-triangle edge or a
/// shadow ray's grazing hit decided the other way in f32). The worst relative error is stated. The
/// hierarchy cut into parts of a seventh of its beams gathers the same sums.
pub(super) fn gpu_glossy_gather_equals_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_cpu::glossy::gather_on_cpu;
    use beam_math::glossy::VolumeMethod;
    use beam_render::glossy::{GlossyOptions, LightVolumes};
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (mut total, mut notes) = (0u64, Vec::new());
    let options = GlossyOptions::new(1, 1);
    for name in crate::glossy::SCENES {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let volumes = LightVolumes::new(&scene, VolumeMethod::Exact, 4);
        let points = crate::glossy::receiver_points(&scene, 10_000, 41);
        let on_cpu = gather_on_cpu(&scene, &volumes, &points, &options);
        let on_gpu = beam_gpu::glossy::GpuGather::new(&gpu, &scene)
            .map_err(|e| e.to_string())?
            .gather(&gpu, &volumes, &points, &options)
            .map_err(|e| e.to_string())?;
        let peak = on_cpu.iter().map(|g| g.irradiance.max_element()).fold(0.0f32, f32::max);
        let (mut differ, mut worst, mut lit, mut walks) = (0u64, 0.0f32, 0u64, 0u64);
        for (c, g) in on_cpu.iter().zip(&on_gpu) {
            walks += u64::from(c.tested != g.tested);
            let error = (g.irradiance - c.irradiance).abs();
            lit += u64::from(c.irradiance != Vec3::ZERO);
            if c.shadowed != g.shadowed || error.cmpgt(1e-3 * c.irradiance.abs() + Vec3::splat(1e-5 * peak)).any() {
                differ += 1;
            } else {
                worst = worst.max((error / (c.irradiance.abs() + Vec3::splat(1e-3 * peak))).max_element());
            }
        }
        if differ * 500 > points.len() as u64 {
            return Err(format!("{name}: {differ} of {} points differ", points.len()));
        }
        // The hierarchy in parts of a seventh of its beams (as one larger than a storage binding
        // is cut): the same sums.
        let parted = beam_gpu::glossy::GpuGather::new(&gpu, &scene)
            .map_err(|e| e.to_string())?
            .with_part_beams(volumes.beams.len() / 7 + 1)
            .gather(&gpu, &volumes, &points, &options)
            .map_err(|e| e.to_string())?;
        for (i, (a, b)) in on_gpu.iter().zip(&parted).enumerate() {
            let bound = 1e-5 * a.irradiance.abs() + Vec3::splat(1e-7 * peak);
            if a.shadowed != b.shadowed
                || a.tested != b.tested
                || (a.irradiance - b.irradiance).abs().cmpgt(bound).any()
            {
                return Err(format!("{name} point {i}: whole hierarchy {a:?}, in parts {b:?}"));
            }
        }
        total += points.len() as u64;
        notes.push(format!(
            "{name}: {differ} of {} differ ({lit} lit), worst {worst:.1e}; {walks} walks took another node in f32",
            points.len()
        ));
    }
    Ok(Outcome { cases: total, note: notes.join("; ") })
}

/// The GPU gather against the CPU's on an area-light scene (`mirror-glass-coarse`: its area light
/// as 4 × 4 stratified point emitters, so many beams and shadow beams): at 2,000 random receiver
/// points the same beams tested, the same shadow masks and irradiance within 1e-3 relative (+1e-5
/// of the largest); at most 0.2% of the points may differ, at most 1% of the tree walks (f32
/// boundaries) and 0.1% of the beams tested. The same points gathered in two
/// interleaved halves must give every point the same result as the whole batch (an invocation
/// depends on its own point only).
pub(super) fn gpu_glossy_gather_area_lights_equal_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_cpu::glossy::gather_on_cpu;
    use beam_math::glossy::VolumeMethod;
    use beam_render::glossy::{GlossyOptions, LightVolumes};
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let name = "mirror-glass-coarse";
    let scene = scene::builtin(name).map_err(|e| e.to_string())?;
    let volumes = LightVolumes::new(&scene, VolumeMethod::Exact, 4);
    if volumes.lights.len() < 16 {
        return Err(format!("{name}: {} emitters, expected an area light's 16", volumes.lights.len()));
    }
    let options = GlossyOptions::new(1, 1);
    let points = crate::glossy::receiver_points(&scene, 2_000, 43);
    let gather = beam_gpu::glossy::GpuGather::new(&gpu, &scene).map_err(|e| e.to_string())?;
    let on_cpu = gather_on_cpu(&scene, &volumes, &points, &options);
    let on_gpu = gather.gather(&gpu, &volumes, &points, &options).map_err(|e| e.to_string())?;
    let peak = on_cpu.iter().map(|g| g.irradiance.max_element()).fold(0.0f32, f32::max);
    let (mut differ, mut walks, mut worst) = (0u64, 0u64, 0.0f32);
    let (tested_cpu, tested_gpu): (u64, u64) =
        on_cpu.iter().zip(&on_gpu).fold((0, 0), |(a, b), (c, g)| (a + u64::from(c.tested), b + u64::from(g.tested)));
    for (c, g) in on_cpu.iter().zip(&on_gpu) {
        walks += u64::from(c.tested != g.tested);
        let error = (g.irradiance - c.irradiance).abs();
        if c.shadowed != g.shadowed || error.cmpgt(1e-3 * c.irradiance.abs() + Vec3::splat(1e-5 * peak)).any() {
            differ += 1;
        } else {
            worst = worst.max((error / (c.irradiance.abs() + Vec3::splat(1e-3 * peak))).max_element());
        }
    }
    let summary = format!(
        "{name} ({} emitters, {} beams, {} nodes): {differ} of {} points differ, worst {worst:.1e}; beams tested \
         {tested_gpu} on the GPU, {tested_cpu} on the CPU ({walks} walks differ)",
        volumes.lights.len(),
        volumes.beams.len(),
        volumes.tree.nodes.len(),
        points.len()
    );
    // The cone-tree walk compares f32 bounds; drivers round differently (NVIDIA's Vulkan driver
    // contracts a·b + c into one FMA, lavapipe does not), so a walk may enter another node at a
    // boundary (9 of 2,000 on an H100, none on lavapipe) and test a few more or fewer beams (40 of
    // 1.8 million), which a correct gather must not turn into another result (`differ` above).
    let walks_off = walks * 100 > points.len() as u64;
    let tested_off = tested_cpu.abs_diff(tested_gpu) * 1000 > tested_cpu;
    if differ * 500 > points.len() as u64 || walks_off || tested_off {
        return Err(summary);
    }
    // Batch independence: every other point, then the rest, against the whole batch.
    let mut batch_dependent = 0u64;
    for parity in 0..2 {
        let half: Vec<(Vec3, Vec3)> = points.iter().skip(parity).step_by(2).copied().collect();
        let again = gather.gather(&gpu, &volumes, &half, &options).map_err(|e| e.to_string())?;
        batch_dependent +=
            again.iter().zip(on_gpu.iter().skip(parity).step_by(2)).filter(|(a, b)| a != b).count() as u64;
    }
    if batch_dependent > 0 {
        return Err(format!("{summary}; {batch_dependent} points gather otherwise in another batch"));
    }
    Ok(Outcome { cases: points.len() as u64, note: summary })
}
