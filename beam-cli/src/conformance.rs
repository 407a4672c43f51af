//! `beam conformance`: the suite of `beam-conformance` with a pass/fail table (cargo feature
//! `conformance`; without it the subcommand only says how to get it, see [`missing`]).

#[cfg(feature = "conformance")]
pub(crate) use suite::{Args, check, run};

/// The options of `beam conformance`, in a build without the suite: taken whatever they are, so
/// that the answer is the message of [`missing`], not a parse error.
#[cfg(not(feature = "conformance"))]
#[derive(clap::Args)]
pub(crate) struct Args {
    #[arg(hide = true, num_args = 0.., trailing_var_arg = true, allow_hyphen_values = true)]
    args: Vec<std::ffi::OsString>,
}

/// What `beam conformance` says in a build without the cargo feature `conformance`.
#[cfg(not(feature = "conformance"))]
pub(crate) fn missing() -> String {
    "this beam was built without the conformance suite (cargo feature `conformance`, off by default so \
     that the binary does not link the test crate); build one with it: cargo build --release -p beam-cli \
     --features conformance"
        .into()
}

#[cfg(feature = "conformance")]
mod suite {
    use beam_conformance::{Backend, Config, properties, run_suite};
    use std::process::ExitCode;

    /// The options of `beam conformance`.
    #[derive(clap::Args)]
    pub(crate) struct Args {
        /// Only this backend (math, bvh, cpu, gpu).
        #[arg(long)]
        pub backend: Option<String>,
        /// Rays of each kind per mesh for the BVH properties (default 2,000 or
        /// $BEAM_CONFORMANCE_RAYS; the BVH issue's full check is 100,000).
        #[arg(long)]
        pub rays: Option<usize>,
        /// Run only the property of this name.
        #[arg(long)]
        pub only: Option<String>,
    }

    /// Check the options before running anything: a known backend, `--rays` at least 1, and an `--only`
    /// that names a property (on that backend).
    pub(crate) fn check(backend: Option<&str>, rays: Option<usize>, only: Option<&str>) -> Result<(), String> {
        let backend = backend.map(Backend::parse).transpose()?;
        if rays == Some(0) {
            return Err("--rays 0: at least 1 ray is needed".into());
        }
        if let Some(name) = only {
            let all = properties();
            let Some(p) = all.iter().find(|p| p.name == name) else {
                let mut names: Vec<_> = all.iter().map(|p| p.name).collect();
                names.sort_unstable();
                return Err(format!("--only {name}: no such property; the properties are: {}", names.join(", ")));
            };
            if let Some(b) = backend.filter(|b| !p.backends.contains(b)) {
                let on: Vec<_> = p.backends.iter().map(|b| b.name()).collect();
                return Err(format!("--only {name}: runs on {} only, not on --backend {}", on.join(", "), b.name()));
            }
        }
        Ok(())
    }

    pub(crate) fn run(backend: Option<&str>, rays: Option<usize>, only: Option<String>) -> Result<ExitCode, String> {
        check(backend, rays, only.as_deref())?;
        let mut config = Config { only, ..Config::default() };
        if let Some(r) = rays {
            config.rays = r;
        }
        let backend = backend.map(Backend::parse).transpose()?;
        let total = properties()
            .iter()
            .filter(|p| config.only.as_deref().is_none_or(|o| o == p.name))
            .map(|p| p.backends.iter().filter(|b| backend.is_none_or(|w| w == **b)).count())
            .sum::<usize>();
        let bar = crate::progress::bar(total as u64, "conformance");
        let reports = run_suite(backend, &config, || bar.inc(1));
        bar.finish_and_clear();
        let width = reports.iter().map(|r| r.property.len()).max().unwrap_or(8);
        println!(
            "{:<width$}  {:<7}  {:<6}  {:>9}  {:>7}  details",
            "property", "backend", "result", "cases", "seconds"
        );
        let (mut failed, mut skipped) = (0, 0);
        for r in &reports {
            let (status, cases, detail) = match &r.result {
                Ok(o) if o.skip_reason().is_some() => {
                    skipped += 1;
                    ("SKIPPED", "-".into(), o.note.clone())
                }
                Ok(o) => ("pass", o.cases.to_string(), format!("{} ({})", o.note, r.cites)),
                Err(e) => {
                    failed += 1;
                    ("FAIL", "-".into(), format!("{e} ({})", r.cites))
                }
            };
            println!(
                "{:<width$}  {:<7}  {:<6}  {:>9}  {:>7.2}  {}",
                r.property,
                r.backend.name(),
                status,
                cases,
                r.seconds,
                detail
            );
        }
        println!("{} passed, {skipped} skipped, {failed} failed", reports.len() - failed - skipped);
        Ok(if failed == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE })
    }
}
