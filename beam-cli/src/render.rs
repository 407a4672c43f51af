//! `beam render` and `beam compare`.

use beam_cpu::glossy::{
    GlossyOptions, LightVolumes, photon_texel, render_glossy, render_glossy_reference, render_glossy_with,
};
use beam_cpu::nonlinear::{
    BeamRenderer, CpuBeams, Degree, NonlinearOptions, render_nonlinear_with, render_smooth_reference_with,
};
use beam_cpu::render::{Image, Method, RenderOptions, Shading, difference, render, side_by_side};
use beam_cpu::scene;
use beam_gpu::nonlinear::GpuBeams;
use beam_math::glam::Vec3;
use beam_math::glossy::VolumeMethod;
use std::path::Path;
use std::process::ExitCode;

/// Options of `beam render`.
pub struct RenderArgs<'a> {
    pub scene: &'a str,
    pub method: &'a str,
    pub backend: &'a str,
    pub degree: &'a str,
    pub texels: u32,
    pub bounces: u32,
    pub smesh: Option<u32>,
    pub shading: &'a str,
    pub spp: u32,
    pub primary_spp: u32,
    pub primary_beams: bool,
    pub volume: &'a str,
    pub linear_gather: bool,
    pub subdivide: u32,
    pub second_order: bool,
    pub photon_kernel: bool,
    pub photons: u64,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub out: &'a Path,
    pub stats: Option<&'a Path>,
}

pub fn run(a: &RenderArgs) -> Result<ExitCode, String> {
    let method = match a.method {
        "beam" | "nonlinear" | "nonlinear-reference" | "glossy" | "glossy-reference" => Method::Beam,
        "ray" => Method::Ray,
        m => {
            return Err(format!(
                "unknown method `{m}` (beam, ray, nonlinear, nonlinear-reference, glossy, glossy-reference)"
            ));
        }
    };
    let shading = match a.shading {
        "fraction" => Shading::Fraction,
        "exact" => Shading::Exact,
        s => return Err(format!("unknown shading `{s}` (fraction, exact)")),
    };
    let scene = match a.smesh {
        Some(n) => scene::builtin_with_smesh(a.scene, n)?,
        None => scene::load(a.scene)?,
    };
    let width = a.width.unwrap_or(scene.camera.width);
    let height = a.height.unwrap_or(if a.width.is_some() {
        width * scene.camera.height / scene.camera.width.max(1)
    } else {
        scene.camera.height
    });
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(format!("image size {width}×{height} out of range (1 to 16384)"));
    }
    let options = RenderOptions {
        method,
        shading,
        spp: a.spp.max(1),
        primary_spp: a.primary_spp.max(1),
        primary_beams: a.primary_beams,
        width,
        height,
        seed: 1,
    };
    if a.method.starts_with("nonlinear") {
        return nonlinear(a, &scene, options);
    }
    if a.method.starts_with("glossy") {
        return glossy(a, &scene, width, height);
    }
    if a.backend != "cpu" {
        return Err(format!("--backend {} renders --method nonlinear and nonlinear-reference only", a.backend));
    }
    let bar = crate::progress::bar(u64::from(height), "render");
    let (image, stats) = render(&scene, &options, || bar.inc(1));
    bar.finish_and_clear();
    image.save_png(a.out)?;
    println!(
        "{}: {} triangles ({} degenerate filtered), {}×{}, {} ({}{}), {:.3} s -> {}",
        scene.name,
        stats.triangles,
        stats.degenerate_triangles,
        width,
        height,
        stats.method,
        stats.shading,
        if method == Method::Ray { format!(", {} spp", stats.spp) } else { String::new() },
        stats.seconds,
        a.out.display()
    );
    if method == Method::Beam && a.primary_beams {
        println!(
            "eye beams: {} visible triangles, {:.2} hit beams per visible triangle, {} fragments, coverage error {:.1e}",
            stats.visible_triangles, stats.hit_beams_per_visible_triangle, stats.fragments, stats.coverage_error
        );
        println!(
            "shadow beams: {}, BVH steps {}, intersections {}, hit beams per pixel {:.2}",
            stats.shadow_beams, stats.bvh_steps, stats.intersections, stats.hit_beams_per_pixel
        );
    }
    write_stats(a.stats, &stats)?;
    Ok(ExitCode::SUCCESS)
}

/// `--method nonlinear` and `nonlinear-reference`.
fn nonlinear(a: &RenderArgs, scene: &scene::Scene, shading: RenderOptions) -> Result<ExitCode, String> {
    let degree = match a.degree {
        "s1" => Degree::S1,
        "s3" => Degree::S3,
        d => return Err(format!("unknown degree `{d}` (s1, s3)")),
    };
    if !(2..=4096).contains(&a.texels) {
        return Err(format!("--texels {} out of range (2 to 4096)", a.texels));
    }
    if !(1..=16).contains(&a.bounces) {
        return Err(format!("--bounces {} out of range (1 to 16)", a.bounces));
    }
    let gpu = gpu_of(a.backend)?;
    let gpu_beams = gpu.as_ref().map(|g| GpuBeams::new(g, scene).map(|b| b.with_light_samples(a.spp))).transpose()?;
    let renderer: &dyn BeamRenderer = match &gpu_beams {
        Some(g) => g,
        None => &CpuBeams,
    };
    let on = gpu.as_ref().map_or_else(|| "CPU".to_string(), |g| g.describe());
    let start = std::time::Instant::now();
    if a.method == "nonlinear-reference" {
        let image = render_smooth_reference_with(scene, &shading, a.photons, renderer)?;
        image.save_png(a.out)?;
        println!(
            "{}: nonlinear reference (rays, smooth mirrors and glass) on {on}, {:.3} s -> {}",
            scene.name,
            start.elapsed().as_secs_f64(),
            a.out.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let (image, stats) = render_nonlinear_with(
        scene,
        &NonlinearOptions { degree, texels: a.texels, bounces: a.bounces, shading },
        renderer,
    )?;
    image.save_png(a.out)?;
    println!(
        "{}: nonlinear {} on {on} ({} texels per beam side), beams per level {:?}, {:.1} triangles per beam after culling, overdraw {:.2}, {} texels shaded, {:.3} s -> {}",
        scene.name,
        stats.degree,
        a.texels,
        stats.beams_per_level,
        stats.triangles_per_beam,
        stats.overdraw,
        stats.texels_shaded,
        stats.seconds,
        a.out.display()
    );
    write_stats(a.stats, &stats)?;
    Ok(ExitCode::SUCCESS)
}

/// `--method glossy` and `glossy-reference`.
fn glossy(a: &RenderArgs, scene: &scene::Scene, width: u32, height: u32) -> Result<ExitCode, String> {
    let method = match a.volume {
        "exact" => VolumeMethod::Exact,
        "tessellated" => VolumeMethod::Tessellated,
        v => return Err(format!("unknown volume `{v}` (exact, tessellated)")),
    };
    let gpu = gpu_of(a.backend)?;
    let start = std::time::Instant::now();
    if a.method == "glossy-reference" {
        let image = render_glossy_reference(scene, width, height, a.photons, 1)?;
        image.save_png(a.out)?;
        println!(
            "{}: glossy reference ({} photons per light), {:.3} s -> {}",
            scene.name,
            a.photons,
            start.elapsed().as_secs_f64(),
            a.out.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    if !(1..=64).contains(&a.subdivide) {
        return Err(format!("--subdivide {} out of range (1 to 64)", a.subdivide));
    }
    let options = GlossyOptions {
        method,
        hierarchy: !a.linear_gather,
        second_order: a.second_order,
        subdivide: a.subdivide,
        filter: if a.photon_kernel { photon_texel(scene) } else { 0.0 },
        ..GlossyOptions::new(width, height)
    };
    let (image, stats) = match &gpu {
        Some(g) => {
            if a.linear_gather || a.photon_kernel {
                return Err(
                    "the GPU gather walks the cone hierarchy at each point (drop --linear-gather and --photon-kernel)"
                        .into(),
                );
            }
            let gather = beam_gpu::glossy::GpuGather::new(g, scene)?;
            let run = |v: &LightVolumes, points: &[(Vec3, Vec3)]| gather.gather(g, v, points, &options);
            render_glossy_with(scene, &options, &CpuBeams, &run)?
        }
        None => render_glossy(scene, &options)?,
    };
    let on = gpu.as_ref().map_or_else(|| "CPU".to_string(), |g| g.describe());
    image.save_png(a.out)?;
    println!(
        "{}: glossy light volumes on {on}, {} beams + {} shadow beams ({:.3} s), {} receiver points, {:.1} beams tested per point ({}), gather {:.3} s, {:.3} s -> {}",
        scene.name,
        stats.beams,
        stats.shadow_beams,
        stats.beam_seconds,
        stats.receivers,
        stats.beams_per_point,
        if a.linear_gather { "linear" } else { "cone hierarchy" },
        stats.gather_seconds,
        stats.seconds,
        a.out.display()
    );
    write_stats(a.stats, &stats)?;
    Ok(ExitCode::SUCCESS)
}

/// The adapter `--backend gpu` asks for (`None` for `cpu`).
fn gpu_of(backend: &str) -> Result<Option<beam_gpu::Gpu>, String> {
    match backend {
        "cpu" => Ok(None),
        "gpu" => beam_gpu::Gpu::new().map(Some),
        b => Err(format!("unknown backend `{b}` (cpu, gpu)")),
    }
}

/// Write `stats` as JSON to `path` (atomically), when given.
fn write_stats(path: Option<&Path>, stats: &impl serde::Serialize) -> Result<(), String> {
    if let Some(p) = path {
        let json = serde_json::to_string_pretty(stats).map_err(|e| e.to_string())?;
        beam_cpu::io::write_atomic(p, json.as_bytes())?;
    }
    Ok(())
}

pub fn compare(a: &Path, b: &Path, out: &Path, scale: f32) -> Result<ExitCode, String> {
    let (ia, ib) = (Image::load(a)?, Image::load(b)?);
    let d = difference(&ia, &ib).map_err(|e| format!("{} vs {}: {e}", a.display(), b.display()))?;
    side_by_side(&ia, &ib, scale)?.save_png(out)?;
    println!("RMSE {:.5}  PSNR {:.2} dB  max {:.4}  (sRGB, [0, 1]) -> {}", d.rmse, d.psnr, d.max, out.display());
    Ok(ExitCode::SUCCESS)
}
