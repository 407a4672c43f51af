//! The `--backend` of `beam bench softshadow` and `beam bench primary` ([`BenchBackend`], one
//! argument group flattened into both): `cpu` (the default, the benches as they were) or `gpu` (the
//! GPU's rows beside the CPU's), and the GPU's adapter.

/// Where a bench runs besides the CPU.
#[derive(clap::Args)]
pub(crate) struct BenchBackend {
    /// `cpu`, or `gpu`: also the GPU's rows, measured against the CPU's in the same run (the
    /// device's milliseconds by timestamp queries, the host's, and the GPU image's PSNR against
    /// the CPU's).
    #[arg(long, default_value = "cpu")]
    backend: String,
}

impl BenchBackend {
    /// Whether `--backend` asks for the GPU: `cpu` or `gpu`, else an error.
    pub(super) fn wants_gpu(&self) -> Result<bool, String> {
        match self.backend.as_str() {
            "cpu" => Ok(false),
            "gpu" => Ok(true),
            b => Err(format!("--backend {b}: unknown backend (expected cpu or gpu)")),
        }
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
