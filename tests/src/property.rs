//! What a property is and what it runs on: the backends, a run's settings, a property's outcome and
//! the property itself. Every property module builds on it; the suite (the crate root) runs them.

use std::fmt;

/// What a property runs against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// The `no_std` math core, checked against independent computations.
    Math,
    /// beam-bvh builders and traversals, checked against brute force.
    Bvh,
    /// beam-cpu renderers: exact soft shadows against closed forms and Monte Carlo.
    Cpu,
    /// beam-gpu: WGSL shaders and pipelines against beam-math and beam-cpu.
    Gpu,
}

impl Backend {
    /// Every backend.
    pub const ALL: [Backend; 4] = [Backend::Math, Backend::Bvh, Backend::Cpu, Backend::Gpu];

    /// The name used on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Backend::Math => "math",
            Backend::Bvh => "bvh",
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
        }
    }

    /// Parse a command-line name.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|b| b.name() == name).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|b| b.name()).collect();
            format!("unknown backend `{name}` (known: {})", names.join(", "))
        })
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Settings of a suite run.
#[derive(Clone, Debug)]
pub struct Config {
    /// Rays of each kind per mesh for the BVH properties (the full check of the BVH issue is 100,000).
    pub rays: usize,
    /// Run only the property of this name.
    pub only: Option<String>,
}

impl Default for Config {
    /// 2,000 rays per kind per mesh, or `$BEAM_CONFORMANCE_RAYS`.
    fn default() -> Self {
        let rays = std::env::var("BEAM_CONFORMANCE_RAYS").ok().and_then(|v| v.parse().ok()).unwrap_or(2_000);
        Self { rays, only: None }
    }
}

/// A passing run: how many cases were checked and a line of measured figures.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// Number of cases checked.
    pub cases: u64,
    /// Measured figures (largest error, counts per branch, ...).
    pub note: String,
}

/// How a skipped run's note begins.
const SKIPPED: &str = "skipped: ";

impl Outcome {
    /// A run that checked nothing because `reason` (no GPU adapter, say): counted as skipped, never
    /// as passed.
    #[must_use]
    pub fn skipped(reason: &str) -> Self {
        Self { cases: 0, note: format!("{SKIPPED}{reason}") }
    }

    /// Why the run was skipped, if it was.
    #[must_use]
    pub fn skip_reason(&self) -> Option<&str> {
        if self.cases == 0 { self.note.strip_prefix(SKIPPED) } else { None }
    }
}

/// Whether `BEAM_REQUIRE_GPU=1` is set (as in CI, which has lavapipe): a GPU property then fails
/// when wgpu finds no adapter instead of being skipped.
#[must_use]
pub fn gpu_required() -> bool {
    std::env::var("BEAM_REQUIRE_GPU").as_deref() == Ok("1")
}

/// True when `backend` is the GPU and wgpu's adapter is a software one (lavapipe in CI), where the
/// heaviest cases of a property take minutes.
#[must_use]
pub fn software_gpu(backend: Backend) -> bool {
    backend == Backend::Gpu && beam_gpu::Gpu::new().is_ok_and(|g| g.is_software())
}

/// A property: a name, the paper section it checks, the backends it runs on, and its body.
pub struct Property {
    /// Unique snake-case name (also the `#[test]` name).
    pub name: &'static str,
    /// The paper section or equation it checks.
    pub cites: &'static str,
    /// Backends the body applies to.
    pub backends: &'static [Backend],
    /// The body: `Ok` with figures, or `Err` with the first counterexample.
    pub body: fn(Backend, &Config) -> Result<Outcome, String>,
}
