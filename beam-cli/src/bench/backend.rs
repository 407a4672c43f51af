//! The `--backend` of `beam bench softshadow` and `beam bench primary`: `cpu` (the default, the
//! benches as they were) or `gpu` (the GPU's rows beside the CPU's), and the GPU's adapter.

/// Whether `--backend` asks for the GPU: `cpu` or `gpu`, else an error.
pub(super) fn wants_gpu(backend: &str) -> Result<bool, String> {
    match backend {
        "cpu" => Ok(false),
        "gpu" => Ok(true),
        b => Err(format!("--backend {b}: unknown backend (expected cpu or gpu)")),
    }
}

/// The adapter of `--backend gpu`, `None` for `cpu`; said on the way.
pub(super) fn adapter(gpu: bool) -> Result<Option<beam_gpu::Gpu>, String> {
    if !gpu {
        return Ok(None);
    }
    let g = beam_gpu::Gpu::new().map_err(|e| format!("--backend gpu: {e}"))?;
    println!("GPU: {}", g.describe());
    Ok(Some(g))
}
