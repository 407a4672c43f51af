//! `beam bench`: benchmarks that print ratios against peers measured in the same run.

mod backend;
pub(crate) mod bvh;
mod checks;
pub(crate) mod glossy;
pub(crate) mod gpu;
pub(crate) mod nonlinear;
pub(crate) mod nonlinear_smesh;
mod peer_set;
#[cfg(feature = "peers")]
mod peers;
pub(crate) mod primary;
mod primary_gpu;
mod primary_shading;
pub(crate) mod primary_sweep;
mod scene_list;
pub(crate) mod softshadow;
mod softshadow_gpu;
mod softshadow_measure;
mod softshadow_plot;
pub(crate) mod softshadow_suite;
mod stats;
mod tracer;

use backend::BenchBackend;
use checks::side;
use clap::Subcommand;
use scene_list::SceneList;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub(crate) enum BenchCommand {
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
        /// Only the SAH builder (no PAH rows): a quicker run.
        #[arg(long)]
        sah_only: bool,
        /// Time the single-thread rows by the thread's CPU time instead of the wall clock (Linux),
        /// so that other processes on a shared machine do not count; the all-core rows stay
        /// wall-clock.
        #[arg(long)]
        cpu_time: bool,
    },
    /// Exact soft shadows by beams against 16/64/256 shadow rays per pixel (and Embree at 256 with
    /// `--features peers`), each with its RMSE against a many-ray reference. With `--suite`
    /// (`--cases`) and `--sweep light`, instead, a table over built-in and generated scenes and over
    /// light sizes on Sponza and the bunny: beams (eye beams and primary rays) against 64 and 256
    /// rays, medians of `--runs`, the bar (beams no slower and no less accurate than 256 rays). With
    /// `--backend gpu`, the GPU's rows are its exact soft shadows (`beam render --backend gpu --method
    /// beam`: primary rays, every shadow beam exact), with beams per second and overflow beams.
    Softshadow {
        /// A built-in scene, a .toml scene or an .obj mesh (which gets an interior camera and a
        /// ceiling light); the single-scene table (default cornell), not with `--suite` or `--sweep`.
        #[arg(long)]
        scene: Option<String>,
        /// Image width and height (default 512; 256 with `--suite` or `--sweep`).
        #[arg(long)]
        size: Option<u32>,
        /// Shadow rays per pixel of the reference (with several lights, shared among them in the
        /// suite).
        #[arg(long, default_value_t = 4096)]
        reference_spp: u32,
        /// Light width and depth as a fraction of the scene box's (for an .obj scene; default 0.1).
        #[arg(long)]
        light_size: Option<f32>,
        /// Write the images and their comparisons with the reference here; with `--suite` or
        /// `--sweep`, also softshadow-suite.csv and softshadow-light-sweep.png.
        #[arg(long, visible_alias = "out")]
        out_dir: Option<PathBuf>,
        /// Run every case of the scene suite: spheres, spheres-36, spheres-256, bunny, spot,
        /// teapot, plant, ground (the shared meshes skipped when absent).
        #[arg(long)]
        suite: bool,
        /// Suite cases to run, comma-separated (implies `--suite`).
        #[arg(long, value_delimiter = ',')]
        cases: Vec<String>,
        /// `light`: sweep the light's edge from 1 % to 100 % of the scene's extent on Sponza and
        /// the bunny (after the suite's cases when both are asked for).
        #[arg(long, value_name = "light")]
        sweep: Option<String>,
        /// Timed runs of every method per scene of `--suite` and `--sweep` (medians reported).
        #[arg(long)]
        runs: Option<u32>,
        #[command(flatten)]
        backend: BenchBackend,
    },
    /// Exact primary visibility by eye beams (001 §3, box-filtered coverage) against 1, 4 and 16
    /// stratified primary rays per pixel (ours, and Embree with `--features peers`) on a flat-shaded
    /// image (a colour per triangle times |cos| of the view angle, black background): seconds, RMSE
    /// against the eye beams' exact image, time relative to the eye beams. With `--sweep`, instead,
    /// eye beams over seeded random views (001 Fig. 7: time against visible triangles). Scenes:
    /// `sponza` and `conference` (the shared OBJ files, skipped when absent; an interior view, the
    /// default), built-ins (e.g. cornell, foliage), .toml scenes or .obj meshes. With `--backend
    /// gpu`, the GPU's rows are its primary rays (1, 4 and 16 per pixel), in the table only.
    Primary {
        #[command(flatten)]
        scenes: SceneList,
        /// Image width and height of the table.
        #[arg(long, default_value_t = 1024)]
        size: u32,
        /// Run the view sweep instead of the table.
        #[arg(long)]
        sweep: bool,
        /// Random cameras per scene of the sweep (default 32); given
        /// without `--sweep`, the sweep runs after the table.
        #[arg(long)]
        cameras: Option<u32>,
        /// Image width and height of the sweep (default 256).
        #[arg(long)]
        sweep_size: Option<u32>,
        /// Seed of the sweep's cameras.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Write the table's images, the sweep's plot (primary-sweep.png) and its CSV here.
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        backend: BenchBackend,
    },
    /// The nonlinear renderer on the GPU (wgpu) against the CPU renderer, frames per second on the
    /// built-in nonlinear scenes (default: all six), each GPU image checked against the CPU's.
    Gpu {
        #[command(flatten)]
        scenes: SceneList,
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
        /// Spawn the beams from a coarse S mesh (000 §7.1) of about N faces, simplified from every
        /// mirror and glass surface (as `beam render --smesh-target`), 4 to 16777216.
        #[arg(long, value_name = "N")]
        smesh_target: Option<u32>,
        /// Find the beams' nearest hits by rasterization (000's draws, the depth test keeping the
        /// nearest) even where the device has the 64-bit atomics of the compute pass.
        #[arg(long)]
        rasterize: bool,
        /// Read every tree level's hits and the eye's mirror and glass hits back for the host, as
        /// before the GPU kept what needs no host (to compare with).
        #[arg(long)]
        read_back: bool,
        /// Read every timed frame's image back, as a one-shot render does, rather than keep it on
        /// the GPU for display (000 §7.3; the warm-up frame's is read back for the PSNR either way).
        #[arg(long)]
        read_image: bool,
        /// Move the eye a little before every timed frame (1e-4 of the scene's diagonal to the
        /// right), so that no beam of a frame's tree is one of the last frame's: the host's work
        /// for a camera in motion, where a still one reuses each beam's preparation.
        #[arg(long)]
        moving: bool,
    },
    /// Glossy light volumes (002) against photon tracing at equal RMSE on the three built-ins of
    /// 002's figures (default: cardioid-ring, pool-caustics, stained-glass), on the CPU and (with an
    /// adapter) the GPU; plots RMSE against time.
    Glossy {
        #[command(flatten)]
        scenes: SceneList,
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
    /// atlas resolution on the mirror teapot, beside the ray-traced reference. With
    /// `--smesh-sweep`: PSNR against beams instead, the teapot's S mesh simplified to
    /// `--targets` faces (000 §7.1), S1 and S3, and the fine S mesh.
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
        /// Sweep S-mesh simplification targets (PSNR against beams) instead of the timings.
        #[arg(long)]
        smesh_sweep: bool,
        /// S-mesh face counts of `--smesh-sweep`, 4 to 16777216 each.
        #[arg(long, value_delimiter = ',', default_value = "100,200,400,700,1000,1500,2500")]
        targets: Vec<u32>,
    },
}

/// Run `beam bench`; with `dry`, only check its arguments.
pub(crate) fn dispatch(what: BenchCommand, dry: bool) -> Result<ExitCode, String> {
    let result = match what {
        BenchCommand::Bvh { scene, json, size, sah_only, cpu_time } => {
            if !(1..=crate::plan::MAX_SIDE as usize).contains(&size) {
                return Err(format!("--size {size} out of range (1 to {})", crate::plan::MAX_SIDE));
            }
            if dry {
                return Ok(ExitCode::SUCCESS);
            }
            let clock = if cpu_time { bvh::Clock::Thread } else { bvh::Clock::Wall };
            bvh::run(&scene, json.as_deref(), size, sah_only, clock)
        }
        BenchCommand::Gpu {
            scenes,
            width,
            height,
            frames,
            degree,
            smesh_target,
            rasterize,
            read_back,
            read_image,
            moving,
        } => {
            side("--width", width)?;
            side("--height", height)?;
            let smesh = smesh_target
                .map(|n| {
                    beam_scene::scene::Simplify::Faces(n)
                        .checked()
                        .map_err(|e| format!("--smesh-target {n} out of range: {e}"))
                })
                .transpose()?;
            let scenes = scenes.or(&gpu::SCENES);
            let degree = match degree.as_str() {
                "s1" => beam_render::nonlinear::Degree::S1,
                "s3" => beam_render::nonlinear::Degree::S3,
                d => return Err(format!("unknown degree `{d}` (s1, s3)")),
            };
            if dry {
                return Ok(ExitCode::SUCCESS);
            }
            gpu::run(&scenes, (width, height), frames, degree, smesh, (rasterize, read_back, read_image, moving))
        }
        BenchCommand::Glossy { scenes, size, reference_photons, subdivide, out } => {
            side("--size", size)?;
            let scenes = scenes.or(&glossy::SCENES);
            if dry {
                return Ok(ExitCode::SUCCESS);
            }
            glossy::run(&scenes, size, reference_photons, subdivide, &out)
        }
        BenchCommand::Nonlinear { size, out, csv, smesh_sweep, targets } => {
            side("--size", size)?;
            for &t in &targets {
                beam_scene::scene::Simplify::Faces(t).checked().map_err(|e| format!("--targets {t}: expected {e}"))?;
            }
            if dry {
                return Ok(ExitCode::SUCCESS);
            }
            match smesh_sweep {
                true => nonlinear_smesh::run(size, &targets, &out, &csv),
                false => nonlinear::run(size, &out, &csv),
            }
        }
        BenchCommand::Primary { scenes, size, sweep, cameras, sweep_size, seed, out, backend } => {
            side("--size", size)?;
            if let Some(s) = sweep_size {
                side("--sweep-size", s)?;
            }
            let gpu = backend.wants_gpu()?;
            if gpu && sweep {
                return Err("--backend gpu is for the table, not --sweep (the sweep times eye beams)".into());
            }
            if dry {
                return Ok(ExitCode::SUCCESS);
            }
            let gpu = backend::adapter(gpu)?;
            let scenes = scenes.or(&primary::SCENES);
            let table = if sweep { Ok(()) } else { primary::run(&scenes, size, out.as_deref(), gpu.as_ref()) };
            table.and_then(|()| match sweep || cameras.is_some() {
                true => primary_sweep::run(&scenes, cameras, sweep_size, seed, out.as_deref()),
                false => Ok(()),
            })
        }
        BenchCommand::Softshadow {
            scene,
            size,
            reference_spp,
            light_size,
            out_dir,
            suite,
            cases,
            sweep,
            runs,
            backend,
        } => {
            let gpu = backend.wants_gpu()?;
            let sweep = match sweep.as_deref() {
                None => false,
                Some("light") => true,
                Some(other) => return Err(format!("--sweep {other}: unknown sweep (light)")),
            };
            if suite || sweep || !cases.is_empty() {
                if scene.is_some() {
                    return Err("--scene is for the single-scene table, not with --suite, --cases or --sweep".into());
                }
                if light_size.is_some() {
                    return Err("--light-size is for the single-scene table; the light sweep sets its own".into());
                }
                let cases = match (suite, cases.is_empty()) {
                    (true, true) => beam_scene::scene::suite::CASES.map(String::from).to_vec(),
                    _ => cases,
                };
                let args = softshadow_suite::Args {
                    cases,
                    sweep,
                    runs: runs.unwrap_or(3),
                    size: size.unwrap_or(256),
                    reference_spp,
                    out: out_dir,
                };
                args.check()?;
                if dry {
                    return Ok(ExitCode::SUCCESS);
                }
                softshadow_suite::run(&args, backend::adapter(gpu)?.as_ref())
            } else {
                if runs.is_some() {
                    return Err("--runs is for --suite and --sweep".into());
                }
                let (scene, size, light_size) =
                    (scene.unwrap_or_else(|| "cornell".into()), size.unwrap_or(512), light_size.unwrap_or(0.1));
                softshadow::check(size, reference_spp, light_size)?;
                if dry {
                    return Ok(ExitCode::SUCCESS);
                }
                softshadow::run(
                    &scene,
                    size,
                    reference_spp,
                    light_size,
                    out_dir.as_deref(),
                    backend::adapter(gpu)?.as_ref(),
                )
            }
        }
    };
    result.map(|()| ExitCode::SUCCESS)
}
