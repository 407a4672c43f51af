//! The `beam` command: runs the conformance suite and the experiments of the beam crates.
//! Thin by design: it parses arguments and calls the libraries.

mod bench;
mod conformance;
mod overdraw;
mod plot;
mod progress;
mod render;

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
        /// Only this backend (math, bvh, cpu).
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
        what: BenchCommand,
    },
    /// Render a scene (default: the built-in Cornell box, exact soft shadows by beams).
    Render {
        /// A built-in scene (cornell, mirror-glass, cornell-point), a .toml scene file or an .obj mesh.
        #[arg(long, default_value = "cornell")]
        scene: String,
        /// Light visibility: `beam` (exact shadow beams) or `ray` (stratified shadow rays); or
        /// `nonlinear` (mirrors by nonlinear beams, 000, with exact shadow beams) and its ground
        /// truth `nonlinear-reference` (mirrors by rays reflected about the interpolated normal); or
        /// `glossy` (caustics and glossy light by light volumes from point lights, 002) and its
        /// ground truth `glossy-reference` (photons).
        #[arg(long, default_value = "beam")]
        method: String,
        /// Where the nonlinear and glossy methods run: `cpu`, or `gpu` (nonlinear: beam atlases, rays
        /// and the shading of diffuse points on the first wgpu adapter, area lights by `--spp`
        /// stratified shadow rays there, where the CPU's are exact; glossy: eye rays and the gather).
        #[arg(long, default_value = "cpu")]
        backend: String,
        /// Nonlinear beam parameterization: `s1` or `s3` (`--method nonlinear`).
        #[arg(long, default_value = "s3")]
        degree: String,
        /// Texels per side of each nonlinear beam's region (`--method nonlinear`).
        #[arg(long, default_value_t = 32)]
        texels: u32,
        /// Levels of the nonlinear beam tree (specular bounces by beams; deeper ones by rays).
        #[arg(long, default_value_t = 2)]
        bounces: u32,
        /// S-mesh resolution of a procedural built-in (facing-mirrors, glass-lens, mirror-teapot,
        /// wavy-lake): quads per mirror side, lens rings, teapot profile steps, water quads per side.
        #[arg(long)]
        smesh: Option<u32>,
        /// `exact` (eq. 1, Lambert's polygon formula) or `fraction` (001 eq. 2).
        #[arg(long, default_value = "exact")]
        shading: String,
        /// Shadow rays per shade point and area light (`--method ray`, and `--backend gpu`).
        #[arg(long, default_value_t = 64)]
        spp: u32,
        /// Primary rays per pixel, stratified, when primary visibility is ray traced.
        #[arg(long, default_value_t = 1)]
        primary_spp: u32,
        /// With `--method beam`: exact primary visibility by eye beams with box-filtered coverage,
        /// and hard shadows from point lights by beams from the visible pieces (001 §4.2), instead
        /// of primary and shadow rays (fast on small scenes; slower than rays on large ones).
        #[arg(long)]
        primary_beams: bool,
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
        /// Photons per point light of the references' caustics (`nonlinear-reference`,
        /// `glossy-reference`).
        #[arg(long, default_value_t = 4_000_000)]
        photons: u64,
        /// Image width (default: the scene camera's).
        #[arg(long)]
        width: Option<u32>,
        /// Image height (default: the scene camera's, or keeping its aspect with --width).
        #[arg(long)]
        height: Option<u32>,
        /// Output PNG.
        #[arg(long, default_value = "beam.png")]
        out: PathBuf,
        /// Also write statistics as JSON.
        #[arg(long)]
        stats: Option<PathBuf>,
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

#[derive(Subcommand)]
enum BenchCommand {
    /// Build with each builder and trace primary, shadow and diffuse rays, 1 thread and all cores,
    /// beside Embree 3 and obvhs (with `--features peers`).
    Bvh {
        /// An OBJ file.
        #[arg(long)]
        scene: PathBuf,
        /// Also write the rows as JSON (`name`, `ray_kind`, `threads`, `build_ms`, `mrays_per_s`).
        #[arg(long)]
        json: Option<PathBuf>,
        /// Image width and height of the primary rays.
        #[arg(long, default_value_t = 512)]
        size: usize,
    },
    /// Exact soft shadows by beams against 16/64/256 shadow rays per pixel (and Embree at 256 with
    /// `--features peers`), each with its RMSE against a many-ray reference.
    Softshadow {
        /// A built-in scene, a .toml scene or an .obj mesh (which gets an interior camera and a
        /// ceiling light).
        #[arg(long, default_value = "cornell")]
        scene: String,
        /// Image width and height.
        #[arg(long, default_value_t = 512)]
        size: u32,
        /// Shadow rays per pixel of the reference.
        #[arg(long, default_value_t = 4096)]
        reference_spp: u32,
        /// Light width and depth as a fraction of the scene box's (for an .obj scene).
        #[arg(long, default_value_t = 0.1)]
        light_size: f32,
        /// Write the images and their comparisons with the reference here.
        #[arg(long)]
        out_dir: Option<PathBuf>,
    },
    /// Exact primary visibility by eye beams (001 §3, box-filtered coverage) against 1, 4 and 16
    /// stratified primary rays per pixel (ours, and Embree with `--features peers`) on a flat-shaded
    /// image (a colour per triangle times |cos| of the view angle, black background): seconds, RMSE
    /// against the eye beams' exact image, time relative to the eye beams. With `--sweep`, instead,
    /// eye beams over seeded random views (001 Fig. 7: time against visible triangles).
    Primary {
        /// Scenes, comma-separated: `sponza` and `conference` (the shared OBJ files, skipped when
        /// absent; an interior view), built-ins (e.g. cornell, foliage), .toml scenes or .obj meshes.
        #[arg(long, value_delimiter = ',')]
        scenes: Vec<String>,
        /// Image width and height of the table.
        #[arg(long, default_value_t = 1024)]
        size: u32,
        /// Run the view sweep instead of the table.
        #[arg(long)]
        sweep: bool,
        /// Random cameras per scene of the sweep (default 8 for .obj meshes, 32 otherwise); given
        /// without `--sweep`, the sweep runs after the table.
        #[arg(long)]
        cameras: Option<u32>,
        /// Image width and height of the sweep (default 128 for .obj meshes, 256 otherwise).
        #[arg(long)]
        sweep_size: Option<u32>,
        /// Seed of the sweep's cameras.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Write the table's images, the sweep's plot (primary-sweep.png) and its CSV here.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// The nonlinear renderer on the GPU (wgpu) against the CPU renderer, frames per second on the
    /// built-in nonlinear scenes, each GPU image checked against the CPU's.
    Gpu {
        /// Built-in scenes, comma-separated (default: all six nonlinear ones).
        #[arg(long, value_delimiter = ',')]
        scenes: Vec<String>,
        /// Image width.
        #[arg(long, default_value_t = 1280)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 1024)]
        height: u32,
        /// Timed GPU frames per scene (after a warm-up frame).
        #[arg(long, default_value_t = 3)]
        frames: u32,
        /// `s1` or `s3`.
        #[arg(long, default_value = "s3")]
        degree: String,
    },
    /// Glossy light volumes (002) against photon tracing at equal RMSE on the three built-ins of
    /// 002's figures, on the CPU and (with an adapter) the GPU; plots RMSE against time.
    Glossy {
        /// Built-in scenes, comma-separated (default: cardioid-ring, pool-caustics, stained-glass).
        #[arg(long, value_delimiter = ',')]
        scenes: Vec<String>,
        /// Image width and height.
        #[arg(long, default_value_t = 512)]
        size: u32,
        /// Photons per light of the reference.
        #[arg(long, default_value_t = 64_000_000)]
        reference_photons: u64,
        /// Sub-triangles per side of each curved scatterer triangle, for every beam frame.
        #[arg(long, default_value_t = 4)]
        subdivide: u32,
        /// Plot (PNG).
        #[arg(long, default_value = "glossy-vs-photons.png")]
        out: PathBuf,
    },
    /// 000 Fig. 10: nonlinear render time (S1, S3) against scene triangles, S-mesh triangles and
    /// atlas resolution on the mirror teapot, beside the ray-traced reference.
    Nonlinear {
        /// Image width and height.
        #[arg(long, default_value_t = 256)]
        size: u32,
        /// Plot (PNG).
        #[arg(long, default_value = "nonlinear-sweep.png")]
        out: PathBuf,
        /// Table of every measurement.
        #[arg(long, default_value = "nonlinear-sweep.csv")]
        csv: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Conformance { backend, rays, only } => conformance::run(backend.as_deref(), rays, only),
        Command::Overdraw { out, csv, points } => overdraw::run(&out, &csv, points),
        Command::Shaders { emit, out } => beam_gpu::shaders::Language::parse(&emit)
            .and_then(|lang| beam_gpu::shaders::emit(lang, &out))
            .map(|files| {
                for f in &files {
                    println!("{}", f.display());
                }
                ExitCode::SUCCESS
            }),
        Command::Render {
            scene,
            method,
            backend,
            degree,
            texels,
            bounces,
            smesh,
            shading,
            spp,
            primary_spp,
            primary_beams,
            volume,
            linear_gather,
            subdivide,
            no_second_order,
            photon_kernel,
            photons,
            width,
            height,
            out,
            stats,
        } => render::run(&render::RenderArgs {
            scene: &scene,
            method: &method,
            backend: &backend,
            degree: &degree,
            texels,
            bounces,
            smesh,
            shading: &shading,
            spp,
            primary_spp,
            primary_beams,
            volume: &volume,
            linear_gather,
            subdivide,
            second_order: !no_second_order,
            photon_kernel,
            photons,
            width,
            height,
            out: &out,
            stats: stats.as_deref(),
        }),
        Command::Compare { a, b, out, scale } => render::compare(&a, &b, &out, scale),
        Command::Bench { what: BenchCommand::Bvh { scene, json, size } } => {
            bench::bvh::run(&scene, json.as_deref(), size).map(|()| ExitCode::SUCCESS)
        }
        Command::Bench { what: BenchCommand::Gpu { scenes, width, height, frames, degree } } => {
            let scenes = if scenes.is_empty() { bench::gpu::SCENES.map(String::from).to_vec() } else { scenes };
            let degree = match degree.as_str() {
                "s1" => Ok(beam_cpu::nonlinear::Degree::S1),
                "s3" => Ok(beam_cpu::nonlinear::Degree::S3),
                d => Err(format!("unknown degree `{d}` (s1, s3)")),
            };
            degree.and_then(|d| bench::gpu::run(&scenes, width, height, frames, d)).map(|()| ExitCode::SUCCESS)
        }
        Command::Bench { what: BenchCommand::Glossy { scenes, size, reference_photons, subdivide, out } } => {
            let scenes = if scenes.is_empty() { bench::glossy::SCENES.map(String::from).to_vec() } else { scenes };
            bench::glossy::run(&scenes, size, reference_photons, subdivide, &out).map(|()| ExitCode::SUCCESS)
        }
        Command::Bench { what: BenchCommand::Nonlinear { size, out, csv } } => {
            bench::nonlinear::run(size, &out, &csv).map(|()| ExitCode::SUCCESS)
        }
        Command::Bench { what: BenchCommand::Primary { scenes, size, sweep, cameras, sweep_size, seed, out } } => {
            let scenes = if scenes.is_empty() { bench::primary::SCENES.map(String::from).to_vec() } else { scenes };
            let table = if sweep { Ok(()) } else { bench::primary::run(&scenes, size, out.as_deref()) };
            table
                .and_then(|()| match sweep || cameras.is_some() {
                    true => bench::primary_sweep::run(&scenes, cameras, sweep_size, seed, out.as_deref()),
                    false => Ok(()),
                })
                .map(|()| ExitCode::SUCCESS)
        }
        Command::Bench { what: BenchCommand::Softshadow { scene, size, reference_spp, light_size, out_dir } } => {
            bench::softshadow::run(&scene, size, reference_spp, light_size, out_dir.as_deref())
                .map(|()| ExitCode::SUCCESS)
        }
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
