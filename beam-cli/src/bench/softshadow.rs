//! `beam bench softshadow`: exact soft shadows by beams against shadow rays (ours at 16, 64 and 256
//! per pixel, Embree at 256 with `--features peers`), each with its error against a many-ray
//! reference, as 001 §5.1 compares them.

use beam_render::image::Image;

use beam_cpu::render::{difference, render, side_by_side};
use beam_gpu::shadow_beam::Walk;
use beam_math::glam::Vec3;
use beam_render::options::{Method, RenderOptions, Shading};
use beam_scene::scene::{self, Camera, Scene};
use std::path::Path;

/// Refuse sizes and counts the benchmark cannot use: `size` 1 to 16384, at least 1 reference ray,
/// and a light size in (0, 1].
pub(crate) fn check(size: u32, reference_spp: u32, light_size: f32) -> Result<(), String> {
    if !(1..=16384).contains(&size) {
        return Err(format!("--size {size} out of range (1 to 16384)"));
    }
    if reference_spp == 0 {
        return Err("--reference-spp 0: at least 1 shadow ray per pixel is needed".into());
    }
    if !(light_size > 0.0 && light_size <= 1.0) {
        return Err(format!("--light-size {light_size} out of range (above 0, at most 1)"));
    }
    Ok(())
}

/// The bench's render options at `size × size`: exact shading (001 eq. 1), one primary ray per
/// pixel centre, or eye beams (exact box-filtered coverage) with `primary_beams` and beams. Beams
/// run as `beam render` does by default: past a budget of `spp` rays' worth of work a shadow beam
/// samples what it left unresolved with `spp` rays.
pub(super) fn options(size: u32, method: Method, spp: u32, seed: u64, primary_beams: bool) -> RenderOptions {
    RenderOptions {
        method,
        shading: Shading::Exact,
        spp,
        primary_beams: primary_beams && method == Method::Beam,
        seed,
        exact: false,
        ..RenderOptions::exact(size, size)
    }
}

/// What a bare mesh gets: the interior view of `beam bench bvh` and a ceiling light of
/// `light_size` × the box's width and depth (radiance `25 (0.1 / light_size)²`, so that the
/// irradiance stays about the same), lowered under the ceiling above the box centre if there is one
/// (the conference room's box top is above its ceiling; Sponza's atrium is open).
pub(super) fn interior_view(scene: &mut Scene, size: u32, light_size: f32) {
    scene.camera = Camera::interior(scene.bounds(), size, size);
    let radiance = Vec3::splat(25.0 * (0.1 / light_size).powi(2));
    scene.lights = vec![scene::interior::ceiling_light(scene, light_size, radiance)];
}

/// `name` without its folders and extension (a mesh's file stem).
fn short_name(name: &str) -> String {
    Path::new(name).file_stem().map_or_else(|| name.to_string(), |s| s.to_string_lossy().into_owned())
}

/// Run the benchmark on `scene_arg` at `size × size`; with `gpu`, also the GPU's exact soft shadows
/// ([`super::softshadow_gpu`]) against the CPU's `beam (exact)`, in the table and in one of their own.
pub(crate) fn run(
    scene_arg: &str,
    size: u32,
    reference_spp: u32,
    light_size: f32,
    out_dir: Option<&Path>,
    gpu: Option<&beam_gpu::Gpu>,
) -> Result<(), String> {
    check(size, reference_spp, light_size)?;
    let mut scene = scene::load(scene_arg).map_err(|e| e.to_string())?;
    scene.bvh.nodes.first().ok_or("empty scene")?;
    if scene_arg.ends_with(".obj") {
        interior_view(&mut scene, size, light_size);
    }
    println!(
        "scene {}: {} triangles, {}×{}, light area {:.3}",
        scene.name,
        scene.stats.triangles,
        size,
        size,
        scene.lights[0].area()
    );
    let options = |method, spp, seed| options(size, method, spp, seed, false);
    let bar = crate::progress::bar(u64::from(size), "reference");
    let (reference, rs) = render(&scene, &options(Method::Ray, reference_spp, 99), || bar.inc(1));
    bar.finish_and_clear();
    println!("reference: {reference_spp} shadow rays per pixel, {:.1} s", rs.seconds);
    let mut rows: Vec<(String, f64, Image, String)> = Vec::new();
    // Primary visibility by rays at pixel centres for every method, as 001 §5.1 times soft shadows.
    let (beam, bs) = render(&scene, &RenderOptions { exact: true, ..options(Method::Beam, 1, 1) }, || {});
    let per_beam = |x: u64| x as f64 / bs.shadow_beams.max(1) as f64;
    rows.push((
        "beam (exact)".into(),
        bs.seconds,
        beam,
        format!(
            "{:.2} hit beams/pixel; per shadow beam: {:.1} BVH steps, {:.1} triangles, {:.1} splits, {:.1} pieces; \
             {:.1} shaft BVH steps/pixel; thread-s primary {:.2}, shadow {:.2}, shading {:.2}",
            bs.hit_beams_per_pixel,
            per_beam(bs.bvh_steps),
            per_beam(bs.triangle_tests),
            per_beam(bs.intersections),
            per_beam(bs.pieces),
            bs.shaft_bvh_steps as f64 / f64::from(size * size),
            bs.primary_seconds,
            bs.shadow_seconds,
            bs.shading_seconds,
        ),
    ));
    let full = RenderOptions { primary_beams: true, exact: true, ..options(Method::Beam, 1, 1) };
    let (img, fs) = render(&scene, &full, || {});
    rows.push((
        "beam + eye beams".into(),
        fs.seconds,
        img,
        format!("{:.2} hit beams per visible triangle", fs.hit_beams_per_visible_triangle),
    ));
    for spp in [16, 64, 256] {
        let (img, st) = render(&scene, &options(Method::Ray, spp, 1), || {});
        rows.push((format!("rays {spp} spp"), st.seconds, img, String::new()));
    }
    #[cfg(feature = "peers")]
    {
        let embree = super::peers::embree_occluder(&scene.triangles)?;
        let (img, st) = beam_cpu::render::render_with(&scene, &options(Method::Ray, 256, 1), &*embree, || {});
        rows.push(("embree3 256 spp".into(), st.seconds, img, String::new()));
    }
    // The GPU's frame with each walk of its shadow beams (beam_gpu::shadow_beam::Walk).
    let mut on_gpu = Vec::new();
    if let Some(g) = gpu {
        for (walk, label) in [(Walk::Alone, "alone"), (Walk::Together, "together")] {
            let bar = crate::progress::bar(u64::from(size), "GPU");
            let exact = RenderOptions { exact: true, ..options(Method::Beam, 1, 1) };
            let run = super::softshadow_gpu::run(g, &scene, (&exact, walk), 1, &|| bar.inc(1))?;
            bar.finish_and_clear();
            let name = format!("{}-{label}", short_name(&scene.name));
            let row = super::softshadow_gpu::Compared::new(name, run, (&rows[0].2, bs.seconds), &reference)?;
            rows.push((format!("gpu {label}"), row.gpu.host_seconds, row.gpu.image.clone(), String::new()));
            on_gpu.push(row);
        }
    }
    let beam_seconds = rows[0].1;
    println!("\n{:<18} {:>9} {:>10} {:>9} {:>14}", "method", "seconds", "RMSE", "PSNR dB", "beam speed-up");
    for (name, seconds, img, extra) in &rows {
        let d = difference(img, &reference).map_err(|e| e.to_string())?;
        println!(
            "{name:<18} {seconds:>9.3} {:>10.5} {:>9.2} {:>14.2}  {extra}",
            d.rmse,
            d.psnr,
            seconds / beam_seconds
        );
    }
    if let Some(g) = gpu {
        println!("\n{}", super::softshadow_gpu::header(g));
        for row in &on_gpu {
            println!("{}", super::softshadow_gpu::line(row));
        }
        println!("{}", super::softshadow_gpu::FOOTNOTE);
    }
    if let Some(dir) = out_dir {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        reference.save_png(&dir.join("reference.png")).map_err(|e| e.to_string())?;
        for (name, _, img, _) in &rows {
            let file = name.split_whitespace().take(2).collect::<Vec<_>>().join("-").replace(['(', ')'], "");
            img.save_png(&dir.join(format!("{file}.png"))).map_err(|e| e.to_string())?;
            side_by_side(img, &reference, 0.05)
                .map_err(|e| e.to_string())?
                .save_png(&dir.join(format!("{file}-vs-reference.png")))
                .map_err(|e| e.to_string())?;
        }
        println!("images in {}", dir.display());
    }
    Ok(())
}
