//! # beam-conformance
//!
//! The conformance suite of beam. A property is one function body that checks something that could
//! fail over thousands of seeded cases; it runs once per backend it applies to. `cargo test` runs
//! every (property, backend) pair through thin `#[test]` wrappers in `tests/tests/`, and
//! `beam conformance [--backend NAME]` runs the same bodies from the CLI and prints a table.
//!
//! Backends: `math` (the beam-math core), `bvh` (beam-bvh against brute force), `cpu` (beam-cpu's
//! renderers) and `gpu` (beam-gpu's shaders and pipelines against their CPU twins, on whatever
//! adapter wgpu finds; Mesa lavapipe in CI).

pub mod bvh;
pub mod cpu;
pub mod generate;
pub mod glossy;
pub mod gpu;
pub mod math;
pub mod nonlinear;
pub mod shadow;

use std::fmt;
use std::time::Instant;

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

/// Runs `f` with `backend`'s nonlinear renderer for `scene`: the CPU's beams, or on `gpu` the GPU's
/// atlases, ray tracer and shading on wgpu's adapter. Without an adapter `Ok(Err(skipped))`, an
/// error under `BEAM_REQUIRE_GPU=1`.
pub fn with_renderer<T>(
    backend: Backend,
    scene: &beam_scene::scene::Scene,
    f: impl FnOnce(&dyn beam_render::nonlinear::BeamRenderer) -> Result<T, String>,
) -> Result<Result<T, Outcome>, String> {
    if backend != Backend::Gpu {
        return f(&beam_cpu::nonlinear::CpuBeams).map(Ok);
    }
    let gpu = match gpu::adapter()? {
        Ok(gpu) => gpu,
        Err(skipped) => return Ok(Err(skipped)),
    };
    f(&beam_gpu::nonlinear::GpuBeams::new(&gpu, scene).map_err(|e| e.to_string())?).map(Ok)
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

/// Every property of the suite.
#[must_use]
pub fn properties() -> Vec<Property> {
    let mut all = math::properties();
    all.extend(bvh::properties());
    all.extend(shadow::properties());
    all.extend(cpu::properties());
    all.extend(nonlinear::properties());
    all.extend(glossy::properties());
    all.extend(gpu::properties());
    all
}

/// One (property, backend) result.
#[derive(Debug)]
pub struct Report {
    /// Property name.
    pub property: &'static str,
    /// Paper reference.
    pub cites: &'static str,
    /// Backend it ran on.
    pub backend: Backend,
    /// The result.
    pub result: Result<Outcome, String>,
    /// Wall time.
    pub seconds: f64,
}

/// Run every property on `backend` (all backends when `None`), in order, calling `done` after each.
pub fn run_suite(backend: Option<Backend>, config: &Config, mut done: impl FnMut()) -> Vec<Report> {
    let mut out = Vec::new();
    for p in properties() {
        if config.only.as_deref().is_some_and(|only| only != p.name) {
            continue;
        }
        for &b in p.backends {
            if backend.is_some_and(|want| want != b) {
                continue;
            }
            let start = Instant::now();
            let result = (p.body)(b, config);
            out.push(Report {
                property: p.name,
                cites: p.cites,
                backend: b,
                result,
                seconds: start.elapsed().as_secs_f64(),
            });
            done();
        }
    }
    out
}

/// Run one property on one backend and panic with its counterexample if it fails (for `#[test]`);
/// a skip prints `SKIPPED` on the terminal.
pub fn check(name: &str, backend: Backend) {
    let p = properties().into_iter().find(|p| p.name == name).unwrap_or_else(|| panic!("no property named {name}"));
    assert!(p.backends.contains(&backend), "{name} does not run on {backend}");
    match (p.body)(backend, &Config::default()) {
        Ok(o) => match o.skip_reason() {
            // Straight to stderr, past the test harness's capture: a skip must be seen.
            Some(reason) => {
                use std::io::Write;
                let _ = writeln!(std::io::stderr(), "SKIPPED {name} [{backend}]: {reason}");
            }
            None => println!("{name} [{backend}]: {} cases, {}", o.cases, o.note),
        },
        Err(e) => panic!("{name} [{backend}] failed: {e}"),
    }
}

/// One `#[test]` per listed property of `backend`, plus a test that every property of that backend
/// has one: `conformance_tests!(Backend::Math, slab_vs_brute_force, …)`.
#[macro_export]
macro_rules! conformance_tests {
    ($backend:expr, $($name:ident),* $(,)?) => {
        $(#[test] fn $name() { $crate::check(stringify!($name), $backend); })*

        #[test]
        fn every_property_has_a_test() {
            let tested = [$(stringify!($name)),*];
            for p in $crate::properties() {
                if p.backends.contains(&$backend) {
                    assert!(tested.contains(&p.name), "property {} has no #[test] wrapper", p.name);
                }
            }
        }
    };
}
