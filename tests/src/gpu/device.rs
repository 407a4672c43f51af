//! The GPU the properties run on, or why they are skipped without one.

use crate::property::Outcome;
use beam_gpu::Gpu;

/// The adapter; without one, `Ok(Err(outcome))` saying why the property is skipped, or the error
/// itself when `BEAM_REQUIRE_GPU=1` ([`crate::property::gpu_required`]).
pub(crate) fn adapter() -> Result<Result<Gpu, Outcome>, String> {
    match Gpu::new() {
        Ok(gpu) => Ok(Ok(gpu)),
        Err(e) if crate::property::gpu_required() => Err(format!("BEAM_REQUIRE_GPU=1 but {e}")),
        Err(e) => Ok(Err(Outcome::skipped(&e.to_string()))),
    }
}
