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
mod output;
mod overdraw;
mod plan;
mod plot;
mod progress;
mod region;
mod render;

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

// Parsed once per run: `render`'s many options need no box.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Run the conformance suite and print a pass/fail table (exit status 1 on any failure).
    Conformance {
        /// Only this backend (math, bvh, cpu, gpu).
        #[arg(long)]
        backend: Option<String>,
        /// Rays of each kind per mesh for the BVH properties (default 2,000 or
        /// $BEAM_CONFORMANCE_RAYS; the BVH issue's full check is 100,000).
        #[arg(long)]
        rays: Option<usize>,
        /// Run only the property of this name.
        #[arg(long)]
        only: Option<String>,
    },
    /// Benchmarks against peers measured in the same run.
    Bench {
        #[command(subcommand)]
        what: bench::BenchCommand,
    },
    /// Render a scene (default: the built-in Cornell box, exact soft shadows by beams).
    Render {
        /// A built-in scene (cornell, mirror-glass, cornell-point, foliage; the soft-shadow suite's
        /// spheres, spheres-36, spheres-256, plant, ground), a .toml scene file, a .gltf/.glb
        /// model or an .obj mesh.
        #[arg(long, default_value = "cornell")]
        scene: String,
        /// Light visibility: `beam` (exact shadow beams) or `ray` (stratified shadow rays); or
        /// `nonlinear` (mirrors by nonlinear beams, 000, with exact shadow beams) and its ground
        /// truth `nonlinear-reference` (mirrors by rays reflected about the interpolated normal); or
        /// `glossy` (caustics and glossy light by light volumes from point lights, and from area
        /// lights as 4×4 stratified points, 002) and its ground truth `glossy-reference` (photons).
        #[arg(long, default_value = "beam")]
        method: String,
        /// Where the method runs: `cpu`, or `gpu` (the first wgpu adapter). On the GPU, `beam` sees
        /// through eye beams (or `--primary-rays`) and `ray` through primary rays, with shadow beams
        /// (exact, each to the end) or shadow rays, in batches, the frame driven by the host;
        /// nonlinear: beam atlases, rays and the shading of diffuse points, area lights by `--spp`
        /// stratified shadow rays, where the CPU's are exact; glossy: eye rays and the gather.
        /// `glossy-reference` runs on the CPU only.
        #[arg(long, default_value = "cpu")]
        backend: String,
        /// Nonlinear beam parameterization: `s1` or `s3` (`--method nonlinear`).
        #[arg(long, default_value = "s3")]
        degree: String,
        /// Texels per side of each nonlinear beam's region, 4 to 4096 (`--method nonlinear`).
        #[arg(long, default_value_t = 32)]
        texels: u32,
        /// Levels of the nonlinear beam tree (specular bounces by beams; deeper ones by rays).
        #[arg(long, default_value_t = 2)]
        bounces: u32,
        /// Area lights cast caustics as N × N stratified point emitters (`--method nonlinear`), 0 to
        /// 8; each costs about as much as a point light's caustics; 0: area lights cast none.
        #[arg(long, default_value_t = beam_cpu::nonlinear::CAUSTIC_STRATA)]
        caustic_strata: u32,
        /// S-mesh resolution of a procedural built-in (facing-mirrors, glass-lens, mirror-teapot,
        /// wavy-lake): quads per mirror side, lens rings, teapot profile steps, water quads per side.
        #[arg(long)]
        smesh: Option<u32>,
        /// Spawn the nonlinear beams from a coarse S mesh (000 §7.1) of about N faces in all,
        /// simplified from every mirror and glass surface without an S mesh of its own in the scene
        /// file (meshoptimizer), 4 to 16777216; the fine surfaces are still the ones rendered.
        #[arg(long, value_name = "N", conflicts_with = "smesh_error")]
        smesh_target: Option<u32>,
        /// Like `--smesh-target`, but simplify while the surface moves by at most this fraction of
        /// its size (above 0, at most 1).
        #[arg(long, value_name = "E")]
        smesh_error: Option<f32>,
        /// `exact` (eq. 1, Lambert's polygon formula) or `fraction` (001 eq. 2).
        #[arg(long, default_value = "exact")]
        shading: String,
        /// Shadow rays per shade point and area light, 1 to 65536 (`--method ray`, and `--backend gpu`;
        /// with `--method beam`, the budget of a shadow beam in rays' worth of work and the rays that
        /// sample what it leaves unresolved, see `--exact`).
        #[arg(long, default_value_t = 64)]
        spp: u32,
        /// Primary rays per pixel when primary visibility is ray traced (`--method ray`, and `beam`
        /// with `--primary-rays`): a perfect square from 1 to 1024 (1, 4, 9, 16, …), the k × k
        /// strata of the pixel; any other number is refused, not rounded.
        #[arg(long, default_value_t = 1)]
        primary_spp: u32,
        /// With `--method beam`: primary visibility by `--primary-spp` stratified primary rays,
        /// and point-light shadows by rays, instead of the default exact eye beams (box-filtered
        /// pixel coverage, 001 §3) with hard shadows by beams from the visible pieces (001 §4.2).
        #[arg(long)]
        primary_rays: bool,
        /// With `--method beam`: how shadow beams take their occluders: `split` (one at a time,
        /// 001 §3.2), `edges` (by their silhouette, boundary and cut edges, integrated exactly), or
        /// `auto` (each cluster of shade points picks the one that did less work); the same image.
        #[arg(long, default_value = "auto")]
        occluders: String,
        /// With `--method beam`: trace every shadow beam to the end. By default a beam whose work
        /// passes `--spp` shadow rays' worth samples the part of the light it left unresolved with
        /// `--spp` rays (exact where they all agree); `--stats` gives the share of exact pixels and
        /// the largest error bound.
        #[arg(long)]
        exact: bool,
        /// Glossy beams' Gaussian volumes (`--method glossy`): `exact` (Owen's T) or `tessellated`
        /// (002 Figs. 11-12).
        #[arg(long, default_value = "exact")]
        volume: String,
        /// Gather over every light beam (`--method glossy`), as 002 does, instead of through the
        /// cone hierarchy.
        #[arg(long)]
        linear_gather: bool,
        /// Split each scatterer triangle into N × N sub-triangles for its light beams (`--method
        /// glossy`; 1: one beam per triangle, as 002 does).
        #[arg(long, default_value_t = 4)]
        subdivide: u32,
        /// Leave out second-order shadows (`--method glossy`), as 002 does.
        #[arg(long)]
        no_second_order: bool,
        /// Read the scattered light through the kernel of `glossy-reference`'s photon map (`--method
        /// glossy`, CPU), so the two estimate the same image: for comparisons with it.
        #[arg(long)]
        photon_kernel: bool,
        /// Photons per light of the references' caustics (`nonlinear-reference`,
        /// `glossy-reference`).
        #[arg(long, default_value_t = 4_000_000)]
        photons: u64,
        /// Image width (default: the scene camera's).
        #[arg(long)]
        width: Option<u32>,
        /// Image height (default: the scene camera's, or keeping its aspect with --width).
        #[arg(long)]
        height: Option<u32>,
        /// Output image: `*.png` (8-bit sRGB, tone-mapped by clamping) or `*.exr` (OpenEXR, linear
        /// radiance as 32-bit floats). Only a new file or a writable regular file is written; it is
        /// checked before the render starts and replaced atomically.
        #[arg(long, default_value = "beam.png")]
        out: PathBuf,
        /// Scale the image by 2^EV before it is written, in PNG (before the sRGB encoding) and EXR
        /// alike; -64 to 64. With an integer EV an EXR holds radiance × 2^EV exactly.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_name = "EV")]
        exposure: f32,
        /// Render band I of N horizontal bands (I from 0 to N − 1; rows ⌊I·H/N⌋ to ⌊(I+1)·H/N⌋,
        /// the same split in every process), for a render farm: the output holds the band and
        /// where it sits in the frame, and `beam merge` joins the bands. Each pixel gets the value
        /// the whole frame's render gives it, bit for bit; the per-pixel work is done for the band
        /// only (docs/guide.md, "Render farms", says what each method still does for the whole
        /// frame).
        #[arg(long, value_name = "I/N", conflicts_with = "crop")]
        tile: Option<String>,
        /// Render the pixels x0 ≤ x < x1, y0 ≤ y < y1 of the frame only (like --tile, a rectangle
        /// of it; `beam merge` joins rectangles that cover the frame).
        #[arg(long, value_name = "x0,y0,x1,y1")]
        crop: Option<String>,
        /// Frame K of the scene file's animated camera (`[[camera.keys]]`); a still camera has
        /// frame 0 only.
        #[arg(long, value_name = "K")]
        frame: Option<u32>,
        /// Also write statistics as JSON (to a file other than --out; written together with it).
        #[arg(long)]
        stats: Option<PathBuf>,
        /// Let a scene file name meshes outside its own folder (through `..`, an absolute path or a
        /// symbolic link); by default they must stay inside it.
        #[arg(long)]
        allow_outside_paths: bool,
        /// The environment, replacing the scene's: what rays that leave the scene see (the
        /// background, mirrors, glass) and the light it sends in. `r,g,b`: a uniform sky of that
        /// linear radiance (lit with exact shadow beams by `--method beam`); a `.hdr` or `.exr`
        /// file: an equirectangular map (+Y up, +X at its centre column, as glTF viewers), whose
        /// light `--spp` cosine-weighted rays a point sample. Seen by `beam` and `ray` only.
        #[arg(long, value_name = "FILE|r,g,b")]
        env: Option<String>,
    },
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
        Command::Conformance { backend, rays, only } => {
            conformance::check(backend.as_deref(), rays, only.as_deref())?;
            done(dry).unwrap_or_else(|| conformance::run(backend.as_deref(), rays, only))
        }
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
        Command::Render {
            scene,
            method,
            backend,
            degree,
            texels,
            bounces,
            caustic_strata,
            smesh,
            smesh_target,
            smesh_error,
            shading,
            spp,
            primary_spp,
            primary_rays,
            occluders,
            exact,
            volume,
            linear_gather,
            subdivide,
            no_second_order,
            photon_kernel,
            photons,
            width,
            height,
            out,
            exposure,
            tile,
            crop,
            frame,
            stats,
            allow_outside_paths,
            env,
        } => {
            let args = plan::RenderArgs {
                scene: &scene,
                method: &method,
                backend: &backend,
                degree: &degree,
                texels,
                bounces,
                caustic_strata,
                smesh,
                smesh_target,
                smesh_error,
                shading: &shading,
                spp,
                primary_spp,
                primary_beams: !primary_rays,
                occluders: &occluders,
                exact,
                volume: &volume,
                linear_gather,
                subdivide,
                second_order: !no_second_order,
                photon_kernel,
                photons,
                width,
                height,
                out: &out,
                exposure,
                tile: tile.as_deref(),
                crop: crop.as_deref(),
                frame,
                stats: stats.as_deref(),
                allow_outside_paths,
                env: env.as_deref(),
                given,
            };
            match dry {
                true => plan::plan(&args, true).map(|_| ExitCode::SUCCESS),
                false => render::run(&args),
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
