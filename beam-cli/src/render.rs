//! `beam render` and `beam compare`.

use crate::method::Kind;
use crate::output::{erased::Json, write_render};
use crate::plan::{Plan, RenderArgs};
use beam_cpu::glossy::{photon_texel, render_glossy, render_glossy_reference_in, render_glossy_with};
use beam_cpu::nonlinear::{CpuBeams, render_smooth_reference_with};
use beam_cpu::render::{render, render_queries};
use beam_gpu::nonlinear::GpuBeams;
use beam_gpu::queries::GpuQueries;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::glossy::{GlossyOptions, LightVolumes};
use beam_render::nonlinear::BeamRenderer;
use beam_render::nonlinear::{NonlinearOptions, render_nonlinear_with};
use beam_render::options::Method;
use std::process::ExitCode;

pub(crate) fn run(a: &RenderArgs) -> Result<ExitCode, String> {
    let plan = crate::plan::plan(a, false)?;
    let (scene, options, (width, height)) = (&plan.scene, plan.options, (plan.options.width, plan.options.height));
    match plan.kind {
        Kind::Nonlinear | Kind::NonlinearReference => return nonlinear(a, &plan),
        Kind::Glossy | Kind::GlossyReference => return glossy(a, &plan),
        Kind::Beam | Kind::Ray => {}
    }
    let method = options.method;
    let bar = crate::progress::bar(u64::from(plan.placement.rect.height()), "render");
    let gpu = gpu_of(plan.gpu)?;
    let (image, stats) = match &gpu {
        // The host drives the frame; rays and shadow beams run on the device in batches.
        Some(g) => {
            let queries = GpuQueries::new(g, scene).map_err(|e| e.to_string())?;
            render_queries(scene, &options, &queries, || bar.inc(1)).map_err(|e| e.to_string())?
        }
        None => render(scene, &options, || bar.inc(1)),
    };
    bar.finish_and_clear();
    write(a, &plan, &image, &stats)?;
    println!(
        "{}: {} triangles ({} degenerate filtered), {}×{}{}, {} ({}{}), {:.3} s -> {}",
        scene.name,
        stats.triangles,
        stats.degenerate_triangles,
        width,
        height,
        part(&plan),
        stats.method,
        stats.shading,
        if method == Method::Ray { format!(", {} spp", stats.spp) } else { String::new() },
        stats.seconds,
        a.out.display()
    );
    if let Some(g) = &gpu {
        let eye = if method == Method::Beam && options.primary_beams && stats.cut_out_regions == 0 {
            format!("eye beams ({} pixels past the device's limits computed on the host)", stats.overflow_pixels)
        } else if stats.cut_out_regions > 0 {
            format!("primary rays ({} per pixel: the frame may show a cut-out)", options.primary_spp)
        } else {
            format!("primary rays ({} per pixel)", options.primary_spp)
        };
        println!(
            "on {}: {eye}, shadow {} on the device; {} beams past its limits traced on the host",
            g.describe(),
            if method == Method::Beam { "beams, each traced to the end," } else { "rays" },
            stats.overflow_beams
        );
    }
    if method == Method::Beam && options.primary_beams && gpu.is_none() {
        println!(
            "eye beams: {} visible triangles, {:.2} hit beams per visible triangle, {} fragments, coverage error {:.1e}",
            stats.visible_triangles, stats.hit_beams_per_visible_triangle, stats.fragments, stats.coverage_error
        );
        println!(
            "shadow beams: {}, BVH steps {}, intersections {}, hit beams per pixel {:.2}",
            stats.shadow_beams, stats.bvh_steps, stats.intersections, stats.hit_beams_per_pixel
        );
    }
    if method == Method::Beam && gpu.is_none() {
        println!(
            "exact pixels {:.1}% ({} lights sampled past their beam's budget, where geometry touches the \
             point ({}) or a cut-out may hide them ({}), largest error bound {:.2e}; {} pixels by primary rays, \
             {} eye beams stopped at their budget, {} regions that may see a cut-out; --exact for all but cut-outs)",
            100.0 * stats.exact_pixel_share,
            stats.sampled_beams,
            stats.contact_beams,
            stats.cut_out_beams,
            stats.max_error_bound,
            stats.ray_pixels,
            stats.over_budget_regions,
            stats.cut_out_regions
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// What `--stats` holds for the references, which count nothing else.
#[derive(serde::Serialize)]
struct ReferenceStats<'a> {
    scene: &'a str,
    method: &'static str,
    on: &'a str,
    width: u32,
    height: u32,
    photons_per_light: u64,
    seconds: f64,
}

/// `--method nonlinear` and `nonlinear-reference`.
fn nonlinear(a: &RenderArgs, plan: &Plan) -> Result<ExitCode, String> {
    let (scene, shading) = (&plan.scene, plan.options);
    let gpu = gpu_of(plan.gpu)?;
    let mut gpu_beams = gpu
        .as_ref()
        .map(|g| GpuBeams::new(g, scene).map(|b| b.with_light_samples(a.spp)))
        .transpose()
        .map_err(|e| e.to_string())?;
    let mut cpu = CpuBeams;
    let renderer: &mut dyn BeamRenderer = match &mut gpu_beams {
        Some(g) => g,
        None => &mut cpu,
    };
    let on = gpu.as_ref().map_or_else(|| "CPU".to_string(), |g| g.describe());
    let start = std::time::Instant::now();
    if plan.kind == Kind::NonlinearReference {
        let image = render_smooth_reference_with(scene, &shading, a.photons, renderer).map_err(|e| e.to_string())?;
        let stats = reference_stats(plan, &on, a.photons, start);
        write(a, plan, &image, &stats)?;
        println!(
            "{}: nonlinear reference (rays, smooth mirrors and glass) on {on}, {:.3} s -> {}",
            scene.name,
            stats.seconds,
            a.out.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let (image, stats) = render_nonlinear_with(
        scene,
        &NonlinearOptions {
            degree: plan.degree,
            texels: a.texels,
            bounces: a.bounces,
            caustic_strata: a.caustic_strata,
            shading,
        },
        renderer,
        &CpuBeams,
    )
    .map_err(|e| e.to_string())?;
    write(a, plan, &image, &stats)?;
    println!(
        "{}: nonlinear {} on {on} ({} texels per beam side, {} S-mesh faces{}), beams per level {:?}, {:.1} triangles per beam after culling, overdraw {:.2}, {} texels shaded, {} caustic beams in {:.3} s, {:.3} s in all -> {}",
        scene.name,
        stats.degree,
        a.texels,
        stats.smesh_faces,
        if stats.coarse_smesh_faces > 0 {
            format!(
                ", {} of them coarse ({} too folded for beams); {} points their child beams do not hold traced by rays",
                stats.coarse_smesh_faces, stats.coarse_faces_by_rays, stats.uncovered_by_beams
            )
        } else {
            String::new()
        },
        stats.beams_per_level,
        stats.triangles_per_beam,
        stats.overdraw,
        stats.texels_shaded,
        stats.caustics.beams,
        stats.caustics.seconds,
        stats.seconds,
        a.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// Write `image` and its `stats` where `a` says (`--out`, `--stats`), as `plan` places them.
fn write(a: &RenderArgs, plan: &Plan, image: &beam_render::image::Image, stats: &dyn Json) -> Result<(), String> {
    write_render(&a.out, image, (plan.placement, a.exposure), a.stats.as_deref().map(|p| (p, stats)))
}

fn reference_stats<'a>(plan: &'a Plan, on: &'a str, photons: u64, start: std::time::Instant) -> ReferenceStats<'a> {
    ReferenceStats {
        scene: &plan.scene.name,
        method: plan.kind.name(),
        on,
        width: plan.options.width,
        height: plan.options.height,
        photons_per_light: photons,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// `--method glossy` and `glossy-reference`.
fn glossy(a: &RenderArgs, plan: &Plan) -> Result<ExitCode, String> {
    let (scene, width, height) = (&plan.scene, plan.options.width, plan.options.height);
    let gpu = gpu_of(plan.gpu)?;
    let start = std::time::Instant::now();
    if plan.kind == Kind::GlossyReference {
        let image = render_glossy_reference_in(scene, (width, height), plan.placement.rect, a.photons, 1)
            .map_err(|e| e.to_string())?;
        let stats = reference_stats(plan, "CPU", a.photons, start);
        write(a, plan, &image, &stats)?;
        println!(
            "{}: glossy reference ({} photons per light), {:.3} s -> {}",
            scene.name,
            a.photons,
            stats.seconds,
            a.out.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let options = GlossyOptions {
        method: plan.volume,
        hierarchy: !a.linear_gather,
        second_order: a.second_order(),
        subdivide: a.subdivide,
        filter: if a.photon_kernel { photon_texel(scene) } else { 0.0 },
        region: plan.options.region,
        ..GlossyOptions::new(width, height)
    };
    // The GPU's gather tests no alpha: with cut-outs, its second-order shadow rays would take them
    // as opaque, so the host gathers (its rays see through them).
    let gpu = gpu.filter(|_| !(options.second_order && scene.has_cut_outs()));
    let (image, stats) = match &gpu {
        Some(g) => {
            let gather = beam_gpu::glossy::GpuGather::new(g, scene).map_err(|e| e.to_string())?;
            let run = |v: &LightVolumes, points: &[(Vec3, Vec3)]| {
                gather.gather(g, v, points, &options).map_err(BackendError::from)
            };
            render_glossy_with(scene, &options, &CpuBeams, &run).map_err(|e| e.to_string())?
        }
        None => render_glossy(scene, &options).map_err(|e| e.to_string())?,
    };
    let on = gpu.as_ref().map_or_else(|| "CPU".to_string(), |g| g.describe());
    write(a, plan, &image, &stats)?;
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
    Ok(ExitCode::SUCCESS)
}

/// `, pixels x0..x1 × y0..y1` of a tile or crop, or nothing for the whole frame.
fn part(plan: &Plan) -> String {
    let r = plan.placement.rect;
    if plan.placement.is_whole() { String::new() } else { format!(" ({r})") }
}

/// The adapter of `--backend gpu` (`None` for `cpu`).
fn gpu_of(gpu: bool) -> Result<Option<beam_gpu::Gpu>, String> {
    if gpu { beam_gpu::Gpu::new().map(Some).map_err(|e| e.to_string()) } else { Ok(None) }
}
