//! The nonlinear renderer of a backend, for the properties that render through either.

use crate::property::{Backend, Outcome};

/// Runs `f` with `backend`'s nonlinear renderer for `scene`: the CPU's beams, or on `gpu` the GPU's
/// atlases, ray tracer and shading on wgpu's adapter. Without an adapter `Ok(Err(skipped))`, an
/// error under `BEAM_REQUIRE_GPU=1`.
pub fn with_renderer<T>(
    backend: Backend,
    scene: &beam_scene::scene::Scene,
    f: impl FnOnce(&mut dyn beam_render::nonlinear::BeamRenderer) -> Result<T, String>,
) -> Result<Result<T, Outcome>, String> {
    if backend != Backend::Gpu {
        return f(&mut beam_cpu::nonlinear::CpuBeams).map(Ok);
    }
    let gpu = match crate::gpu::adapter()? {
        Ok(gpu) => gpu,
        Err(skipped) => return Ok(Err(skipped)),
    };
    f(&mut beam_gpu::nonlinear::GpuBeams::new(&gpu, scene).map_err(|e| e.to_string())?).map(Ok)
}
