//! `beam bench softshadow --suite` and `--sweep light`: exact soft shadows by beams against our
//! shadow rays (64 and 256 per pixel) and Embree's (256, `--features peers`) on scenes the bench
//! does not choose to suit beams ([`beam_scene::scene::suite`]), and over light sizes from 1 % to
//! 100 % of the scene's extent on Sponza and the bunny. Each row: medians of `--runs` timings of
//! every method in one process, RMSE against many-ray references, the beams' pieces and hit beams
//! per pixel, and the bar (beams no slower than 256 rays, and no less accurate).

use super::softshadow::{interior_view, options};
use super::softshadow_gpu;
use super::softshadow_measure::{Images, METHODS, Row, measure};
use beam_cpu::render::render;
use beam_gpu::shadow_beam::Walk;
use beam_render::options::{Method, RenderOptions};
use beam_scene::io::write_atomic;
use beam_scene::scene::suite::{self, CASES, Case, SWEEP};
use std::path::{Path, PathBuf};

/// The table's file in `--out`.
const CSV: &str = "softshadow-suite.csv";

/// The suite's arguments.
pub(crate) struct Args {
    /// Suite cases to run (none: only the sweep).
    pub cases: Vec<String>,
    /// Run the light sweep.
    pub sweep: bool,
    /// Timed runs of each method per scene.
    pub runs: u32,
    /// Image width and height.
    pub size: u32,
    /// Shadow rays per pixel of the references.
    pub reference_spp: u32,
    /// Folder of the CSV, the plot and the images.
    pub out: Option<PathBuf>,
}

/// The GPU's CSV in `--out` (`--backend gpu`).
const GPU_CSV: &str = "softshadow-suite-gpu.csv";

impl Args {
    /// Refuse what the suite cannot run, naming the option.
    pub(crate) fn check(&self) -> Result<(), String> {
        super::checks::side("--size", self.size)?;
        if self.reference_spp == 0 {
            return Err("--reference-spp 0: at least 1 shadow ray per pixel is needed".into());
        }
        if !(1..=100).contains(&self.runs) {
            return Err(format!("--runs {} out of range (1 to 100)", self.runs));
        }
        if let Some(bad) = self.cases.iter().find(|c| !CASES.contains(&c.as_str())) {
            return Err(format!("--cases: unknown case `{bad}` (cases: {})", CASES.join(", ")));
        }
        Ok(())
    }
}

/// Run the suite's cases, then the light sweep, printing a row per scene; write the CSV, the plot
/// and the images to `args.out`. With `gpu`, each scene's GPU frame too ([`super::softshadow_gpu`],
/// `args.runs` times, against the CPU's exact soft shadows from the same primary rays), a line
/// under its row and a table at the end.
pub(crate) fn run(args: &Args, gpu: Option<&beam_gpu::Gpu>) -> Result<(), String> {
    args.check()?;
    println!(
        "softshadow suite: {0}×{0}, {1} threads, medians of {2} runs, references of {3} shadow rays per pixel; \
         rays per pixel are shared among the lights",
        args.size,
        rayon::current_num_threads(),
        args.runs,
        args.reference_spp
    );
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).map_err(|e| format!("--out {}: {e}", dir.display()))?;
    }
    println!("{}", header());
    let mut rows = Vec::new();
    let mut gpu_rows = Vec::new();
    // The CSV is rewritten after every row, so that a run stopped early keeps what it measured.
    let mut row = |scene: &beam_scene::scene::Scene, case: &str, light: Option<f32>| -> Result<(), String> {
        let (r, images) = measure(scene, case, light, args.size, args.runs, args.reference_spp)?;
        println!("{}", line(&r));
        if let Some(g) = gpu {
            gpu_rows.push(gpu_row(g, scene, args, &r, &images)?);
            println!("  gpu: {}", softshadow_gpu::line(&gpu_rows[gpu_rows.len() - 1]));
        }
        rows.push(r);
        if let Some(dir) = &args.out {
            write_images(dir, &rows[rows.len() - 1], &images)?;
            write_atomic(&dir.join(CSV), csv(&rows).as_bytes()).map_err(|e| e.to_string())?;
            if gpu.is_some() {
                let csv = softshadow_gpu::csv(&gpu_rows);
                write_atomic(&dir.join(GPU_CSV), csv.as_bytes()).map_err(|e| e.to_string())?;
            }
        }
        Ok(())
    };
    for name in &args.cases {
        match suite::case(name).map_err(|e| e.to_string())? {
            Case::Built(scene) => row(&scene, name, None)?,
            Case::Absent(why) => println!("skipping {name}: {why}"),
        }
    }
    if args.sweep {
        if let Some(mut loaded) = super::primary::load("sponza")? {
            for f in SWEEP {
                interior_view(&mut loaded.scene, args.size, f);
                row(&loaded.scene, "sponza", Some(f))?;
            }
        }
        match suite::case("bunny").map_err(|e| e.to_string())? {
            Case::Built(mut scene) => {
                let base = scene.lights.clone();
                for f in SWEEP {
                    scene.lights.clone_from(&base);
                    scene.lights = vec![suite::light_of_size(&scene, f).ok_or("the bunny's light is not a quad")?];
                    row(&scene, "bunny", Some(f))?;
                }
            }
            Case::Absent(why) => println!("skipping the bunny's sweep: {why}"),
        }
    }
    if let (Some(g), false) = (gpu, gpu_rows.is_empty()) {
        println!("\n{}", softshadow_gpu::header(g));
        gpu_rows.iter().for_each(|r| println!("{}", softshadow_gpu::line(r)));
        println!("{}", softshadow_gpu::FOOTNOTE);
    }
    let passed = rows.iter().filter(|r| r.pass()).count();
    println!(
        "bar (beams from primary rays ≤ rays 256 from the same rays, in time and in RMSE): {passed} of {} rows pass",
        rows.len()
    );
    if let (Some(dir), false) = (&args.out, rows.is_empty()) {
        println!("wrote {}", dir.join(CSV).display());
        if rows.iter().any(|r| r.light.is_some()) {
            let png = dir.join("softshadow-light-sweep.png");
            super::softshadow_plot::light_sweep(&png, &rows)?;
            println!("wrote {}", png.display());
        }
    }
    Ok(())
}

/// `scene`'s GPU frame ([`softshadow_gpu::run`], `args.runs` times) against the CPU's exact soft
/// shadows from the same primary rays (`render` with `exact`, as many times, medians): the suite's
/// own beams from primary rays run past a budget into sampling (most of all with many lights),
/// which the GPU's frame never does. The CPU runs once before the GPU's, then in turn with them.
fn gpu_row(
    gpu: &beam_gpu::Gpu,
    scene: &beam_scene::scene::Scene,
    args: &Args,
    r: &Row,
    images: &Images,
) -> Result<softshadow_gpu::Compared, String> {
    let options = options(args.size, Method::Beam, r.rays_per_light[1], 1, false);
    let options = RenderOptions { exact: true, ..options };
    let bar = crate::progress::bar(2 * u64::from(args.size) * u64::from(args.runs), "GPU");
    bar.set_message(label(r));
    let (mut cpu, mut seconds) = (None, Vec::new());
    for _ in 0..args.runs {
        let (img, st) = render(scene, &options, || bar.inc(1));
        seconds.push(st.seconds);
        cpu.get_or_insert(img);
    }
    let run = softshadow_gpu::run(gpu, scene, (&options, Walk::Alone), args.runs, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let cpu = (&cpu.ok_or("no CPU run")?, super::stats::median(seconds));
    softshadow_gpu::Compared::new(label(r), run, cpu, &images.reference)
}

/// A row's name in file names: the case, and the light size of a sweep row.
fn label(r: &Row) -> String {
    match r.light {
        Some(f) => format!("{}-light{f}", r.case),
        None => r.case.clone(),
    }
}

fn write_images(dir: &Path, r: &Row, images: &Images) -> Result<(), String> {
    let name = label(r);
    let written = [
        ("beam", &images.beam),
        ("beam-primary-rays", &images.beam_rays),
        ("rays256", &images.rays),
        ("reference", &images.reference),
    ];
    for (what, img) in written {
        img.save_png(&dir.join(format!("{name}-{what}.png"))).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn header() -> String {
    format!(
        "{:<12} {:>5} {:>7} {:>6} | {:>8} {:>8} {:>8} {:>8} {:>8} | {:>6} {:>6} | {:>8} {:>8} {:>8} {:>8} {:>8} | {:>7} {:>7} {:>9} {:>6} | bar\n\
         {:<12} {:>5} {:>7} {:>6} | {:>8} {:>8} {:>8} {:>8} {:>8} | {:>6} {:>6} | {:>8} {:>8} {:>8} {:>8} {:>8} | {:>7} {:>7} {:>9} {:>6} |",
        "case",
        "light",
        "tris",
        "lights",
        "beam s",
        "b·rays s",
        "r64 s",
        "r256 s",
        "emb256 s",
        "br/256",
        "br/64",
        "RMSE",
        "RMSE",
        "RMSE",
        "RMSE",
        "RMSE",
        "pieces",
        "hit",
        "shadow",
        "exact",
        "",
        "",
        "",
        "",
        "",
        "",
        "",
        "",
        "",
        "",
        "",
        "beam",
        "b·rays",
        "r64",
        "r256",
        "emb256",
        "/pixel",
        "/pixel",
        "beams",
        "%",
    )
}

fn line(r: &Row) -> String {
    let f = |v: Option<f64>, p: usize| v.map_or_else(|| "-".to_string(), |v| format!("{v:.p$}"));
    let ratio = |i: usize| r.seconds[1].zip(r.seconds[i]).map(|(b, o)| b / o);
    format!(
        "{:<12} {:>5} {:>7} {:>6} | {:>8} {:>8} {:>8} {:>8} {:>8} | {:>6} {:>6} | {:>8} {:>8} {:>8} {:>8} {:>8} | {:>7.2} {:>7.2} {:>9} {:>6.1} | {}",
        r.case,
        r.light.map_or_else(|| "-".to_string(), |l| l.to_string()),
        r.triangles,
        r.lights,
        f(r.seconds[0], 3),
        f(r.seconds[1], 3),
        f(r.seconds[2], 3),
        f(r.seconds[3], 3),
        f(r.seconds[4], 3),
        f(ratio(3), 2),
        f(ratio(2), 2),
        f(r.rmse[0], 5),
        f(r.rmse[1], 5),
        f(r.rmse[2], 5),
        f(r.rmse[3], 5),
        f(r.rmse[4], 5),
        r.pieces_per_pixel,
        r.hit_beams_per_pixel,
        r.shadow_beams,
        100.0 * r.exact_share,
        if r.pass() { "PASS" } else { "FAIL" }
    )
}

/// Every row, one line each; empty fields for what was not measured.
fn csv(rows: &[Row]) -> String {
    let keys: [&str; METHODS.len()] = ["beam", "beam_primary_rays", "rays64", "rays256", "embree256"];
    let mut out = String::from("case,light_fraction,triangles,lights,rays64_per_light,rays256_per_light,");
    out.push_str("reference_rays_per_light,");
    out.push_str(&keys.map(|k| format!("{k}_s")).join(","));
    out.push_str(",beam_primary_rays_over_rays256,beam_primary_rays_over_rays64,");
    out.push_str(&keys.map(|k| format!("{k}_rmse")).join(","));
    out.push_str(
        ",beam_rmse_vs_pixel_centres,pieces_per_pixel,hit_beams_per_pixel,shadow_beams,exact_pixel_share,pass\n",
    );
    let opt = |v: Option<f64>| v.map_or_else(String::new, |v| v.to_string());
    for r in rows {
        let ratio = |i: usize| opt(r.seconds[1].zip(r.seconds[i]).map(|(b, o)| b / o));
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            r.case,
            r.light.map_or_else(String::new, |l| l.to_string()),
            r.triangles,
            r.lights,
            r.rays_per_light[0],
            r.rays_per_light[1],
            r.rays_per_light[2],
            r.seconds.map(opt).join(","),
            ratio(3),
            ratio(2),
            r.rmse.map(opt).join(","),
            r.rmse_beam_centres,
            r.pieces_per_pixel,
            r.hit_beams_per_pixel,
            r.shadow_beams,
            r.exact_share,
            r.pass(),
        ));
    }
    out
}
