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
pub mod property;
pub mod renderer;
pub mod shadow;

pub use property::{Backend, Config, Outcome, Property, gpu_required, software_gpu};
pub use renderer::with_renderer;

use std::time::Instant;

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
