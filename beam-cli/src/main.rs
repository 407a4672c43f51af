//! The `beam` command: runs the conformance suite and the experiments of the beam crates.
//! Thin by design: it parses arguments and calls the libraries.

mod conformance;
mod overdraw;
mod progress;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// beam: exact, noise-free beam tracing.
#[derive(Parser)]
#[command(name = "beam", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the conformance suite and print a pass/fail table (exit status 1 on any failure).
    Conformance {
        /// Only this backend (math, bvh).
        #[arg(long)]
        backend: Option<String>,
        /// Rays of each kind per mesh for the BVH properties (default 2,000 or
        /// $BEAM_CONFORMANCE_RAYS; the BVH issue's full check is 100,000).
        #[arg(long)]
        rays: Option<usize>,
    },
    /// Reproduce 000 Fig. 7: overdraw of our bounding triangles vs the general case alone.
    Overdraw {
        /// Plot of both sweeps (PNG).
        #[arg(long, default_value = "overdraw.png")]
        out: PathBuf,
        /// Table of every measurement.
        #[arg(long, default_value = "overdraw.csv")]
        csv: PathBuf,
        /// Points per sweep.
        #[arg(long, default_value_t = 24)]
        points: usize,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Conformance { backend, rays } => conformance::run(backend.as_deref(), rays),
        Command::Overdraw { out, csv, points } => overdraw::run(&out, &csv, points),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
