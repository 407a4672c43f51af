//! The `beam` command: runs the conformance suite and the experiments of the beam crates.
//! Thin by design: it parses arguments and calls the libraries.

mod allocator;
mod bench;
mod compare;
mod conformance;
#[cfg(test)]
mod fuzz;
mod limits;
mod merge;
mod method;
mod output;
mod overdraw;
mod plan;
mod plot;
mod progress;
mod region;
mod render;
mod unused;

use clap::parser::ValueSource;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// beam: exact, noise-free beam tracing.
#[derive(Parser)]
#[command(name = "beam", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[expect(clippy::large_enum_variant, reason = "parsed once per run: `render`'s many options need no box")]
#[derive(Subcommand)]
enum Command {
    /// Run the conformance suite and print a pass/fail table (exit status 1 on any failure).
    #[cfg(feature = "conformance")]
    Conformance(conformance::Args),
    /// Run the conformance suite: not in this build (cargo feature `conformance`; build with
    /// `cargo build --release -p beam-cli --features conformance`).
    #[cfg(not(feature = "conformance"))]
    Conformance(conformance::Args),
    /// Benchmarks against peers measured in the same run.
    Bench {
        #[command(subcommand)]
        what: bench::BenchCommand,
    },
    /// Render a scene (default: the built-in Cornell box, exact soft shadows by beams).
    Render(plan::RenderArgs),
    /// Join the tiles of `beam render --tile` or `--crop` (PNG or EXR) into the whole frame: they
    /// must share the frame's size, not overlap, and cover it. The result is the file a
    /// one-process render writes, byte for byte.
    Merge {
        /// The tiles, all PNG or all EXR (the format of --out).
        #[arg(required = true)]
        tiles: Vec<PathBuf>,
        /// The whole frame (`*.png` or `*.exr`, as the tiles); not one of the tiles.
        #[arg(long)]
        out: PathBuf,
    },
    /// Compare two images: RMSE and PSNR, and a side-by-side picture with an error map.
    Compare {
        /// First image.
        a: PathBuf,
        /// Second image.
        b: PathBuf,
        /// Side-by-side output (a | b | error).
        #[arg(long, default_value = "diff.png")]
        out: PathBuf,
        /// Error (sRGB units) shown at full scale in the error map.
        #[arg(long, default_value_t = 0.1)]
        scale: f32,
    },
    /// Write the WGSL shaders translated by naga (SPIR-V, GLSL, MSL or HLSL), for engines that take
    /// them into their own pipelines.
    Shaders {
        /// `spv`, `glsl`, `msl` or `hlsl`.
        #[arg(long)]
        emit: String,
        /// Output directory (created).
        #[arg(long)]
        out: PathBuf,
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

/// Parse `args` (the program name first): the command line, and the clap ids of the `render`
/// options given on it (not defaulted), which `beam render` refuses where they do not apply.
fn parse_from<I, T>(args: I) -> Result<(Cli, Vec<String>), clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let matches = Cli::command().try_get_matches_from(args)?;
    let cli = Cli::from_arg_matches(&matches)?;
    let given = matches
        .subcommand_matches("render")
        .map(|m| {
            m.ids()
                .filter(|id| m.value_source(id.as_str()) == Some(ValueSource::CommandLine))
                .map(ToString::to_string)
                .collect()
        })
        .unwrap_or_default();
    Ok((cli, given))
}

fn main() -> ExitCode {
    allocator::keep_freed_memory();
    output::stop_cleanly_on_signals();
    let (cli, given) = parse_from(std::env::args_os()).unwrap_or_else(|e| e.exit());
    let code = match run(cli, &given, false) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    };
    output::wait_if_stopped();
    code
}

/// Run a command; with `dry`, only check its arguments (nothing is rendered, read past the
/// headers, or written).
fn run(cli: Cli, given: &[String], dry: bool) -> Result<ExitCode, String> {
    let done = |dry: bool| if dry { Some(Ok(ExitCode::SUCCESS)) } else { None };
    match cli.command {
        #[cfg(feature = "conformance")]
        Command::Conformance(c) => {
            conformance::check(c.backend.as_deref(), c.rays, c.only.as_deref())?;
            done(dry).unwrap_or_else(|| conformance::run(c.backend.as_deref(), c.rays, c.only))
        }
        #[cfg(not(feature = "conformance"))]
        Command::Conformance(_) => Err(conformance::missing()),
        Command::Overdraw { out, csv, points } => {
            if points < 2 {
                return Err(format!("--points {points} out of range (at least 2)"));
            }
            done(dry).unwrap_or_else(|| overdraw::run(&out, &csv, points))
        }
        Command::Shaders { emit, out } => {
            let lang = beam_gpu::shaders::Language::parse(&emit).map_err(|e| e.to_string())?;
            done(dry).unwrap_or_else(|| {
                beam_gpu::shaders::emit(lang, &out)
                    .map(|files| {
                        for f in &files {
                            println!("{}", f.display());
                        }
                        ExitCode::SUCCESS
                    })
                    .map_err(|e| e.to_string())
            })
        }
        Command::Render(mut args) => {
            args.given = given.to_vec();
            match dry {
                true => plan::plan(&args, true).map(|_| ExitCode::SUCCESS),
                false => {
                    // Start the threads while the scene loads: a thread the kernel has just made
                    // waited up to 3 ms for a core here, longer than a small render takes.
                    rayon::spawn_broadcast(|_| {});
                    render::run(&args)
                }
            }
        }
        Command::Merge { tiles, out } => match dry {
            true => merge::plan(&tiles, &out, true).map(|_| ExitCode::SUCCESS),
            false => merge::merge(&tiles, &out),
        },
        Command::Compare { a, b, out, scale } => match dry {
            true => compare::plan(&a, &b, &out, scale, true).map(|_| ExitCode::SUCCESS),
            false => compare::compare(&a, &b, &out, scale),
        },
        Command::Bench { what } => bench::dispatch(what, dry),
    }
}
