//! `beam bench nonlinear --smesh-sweep`: image quality against the number of beams (after 000
//! Fig. 10 and §7.1) on the mirror teapot, the fine mesh rendered and its S mesh simplified to a
//! sweep of face counts (meshoptimizer), S1 and S3: beams, PSNR against the ray-traced reference and
//! seconds per point, as a CSV table and a plot; the fine S mesh (the rendered triangles themselves)
//! is the last row. Each row also counts what rays did under the coarse faces: the faces too folded
//! for beams and the points whose scattered ray no child beam holds.

use beam_cpu::nonlinear::{render_nonlinear, render_smooth_reference};
use beam_cpu::render::difference;
use beam_render::nonlinear::Degree;
use beam_render::nonlinear::{CAUSTIC_STRATA, NonlinearOptions};
use beam_render::options::RenderOptions;
use beam_scene::io::write_atomic;
use beam_scene::scene::Simplify;
use beam_scene::scene::showcase::mirror_teapot;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// Photons per light of the reference's caustics (`beam render --method nonlinear-reference`'s
/// default).
const REFERENCE_PHOTONS: u64 = 4_000_000;

/// One render of the sweep.
struct Row {
    /// Simplification target (`None`: the fine S mesh).
    target: Option<u32>,
    degree: Degree,
    smesh_faces: u64,
    beams: u64,
    psnr: f64,
    seconds: f64,
    /// Coarse faces too folded for beams (their points traced by rays).
    folded: u64,
    /// Points under coarse faces whose child beams do not hold their scattered rays (traced by rays).
    uncovered: u64,
}

/// Render the teapot (`size`², 32 texels, two levels, the area light's caustics by 2 × 2 strata:
/// `beam render --method nonlinear`'s defaults) with its S mesh simplified to each of `targets`
/// faces and with the fine S mesh, S1 and S3; write the table to `csv` and the plot to `out`.
pub(crate) fn run(size: u32, targets: &[u32], out: &Path, csv: &Path) -> Result<(), String> {
    let shading = RenderOptions::exact(size, size);
    let mut scene = mirror_teapot(24, 16);
    let reference = render_smooth_reference(&scene, &shading, REFERENCE_PHOTONS);
    let points: Vec<Option<u32>> = targets.iter().copied().map(Some).chain([None]).collect();
    let bar = crate::progress::bar(2 * points.len() as u64, "S-mesh sweep");
    let mut rows = Vec::new();
    for &target in &points {
        scene.smesh.rest = target.map(Simplify::Faces);
        for degree in [Degree::S1, Degree::S3] {
            let options = NonlinearOptions { degree, texels: 32, bounces: 2, caustic_strata: CAUSTIC_STRATA, shading };
            let (image, stats) = render_nonlinear(&scene, &options).map_err(|e| e.to_string())?;
            let psnr = difference(&image, &reference).map_err(|e| e.to_string())?.psnr;
            let beams = stats.beams_per_level.iter().sum();
            let (folded, uncovered) = (stats.coarse_faces_by_rays, stats.uncovered_by_beams);
            let (smesh_faces, seconds) = (stats.smesh_faces, stats.seconds);
            rows.push(Row { target, degree, smesh_faces, beams, psnr, seconds, folded, uncovered });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let mut text = String::from("target,degree,smesh_faces,folded_faces,uncovered_points,beams,psnr_db,seconds\n");
    for r in &rows {
        let target = r.target.map_or("fine".to_string(), |t| t.to_string());
        let degree = format!("{:?}", r.degree).to_lowercase();
        let (faces, folded, uncovered) = (r.smesh_faces, r.folded, r.uncovered);
        let _ =
            writeln!(text, "{target},{degree},{faces},{folded},{uncovered},{},{:.3},{:.3}", r.beams, r.psnr, r.seconds);
        println!(
            "S mesh {target:>5} ({faces:>5} faces, {folded:>3} folded) {degree}: {:>6} beams, {:6.2} dB, {uncovered:>5} \
             points by rays, {:7.2} s",
            r.beams, r.psnr, r.seconds
        );
    }
    write_atomic(csv, text.as_bytes()).map_err(|e| e.to_string())?;
    plot(out, size, &rows)?;
    println!("wrote {} and {}", out.display(), csv.display());
    Ok(())
}

fn plot(path: &Path, size: u32, rows: &[Row]) -> Result<(), String> {
    crate::plot::png(path, (900, 600), |root| {
        let (x0, x1) =
            rows.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), r| (lo.min(r.beams as f64), hi.max(r.beams as f64)));
        let (y0, y1) =
            rows.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| (lo.min(r.psnr), hi.max(r.psnr)));
        let mut chart = ChartBuilder::on(root)
            .caption(format!("PSNR vs beams, mirror teapot {size}², simplified S meshes"), ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d((x0.max(1.0) * 0.8..x1 * 1.25).log_scale(), (y0 - 0.5)..(y1 + 0.5))
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("beams (both tree levels)")
            .y_desc("PSNR against the ray-traced reference, dB")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .draw()
            .map_err(|e| e.to_string())?;
        let curve = |degree: Degree, fine: bool| -> Vec<(f64, f64)> {
            let mut p: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.degree == degree && r.target.is_none() == fine)
                .map(|r| (r.beams as f64, r.psnr))
                .collect();
            p.sort_by(|a, b| a.0.total_cmp(&b.0));
            p
        };
        let series = vec![
            ("S1, simplified S mesh", BLUE, curve(Degree::S1, false)),
            ("S3, simplified S mesh", RED, curve(Degree::S3, false)),
            ("S1, fine S mesh", RGBColor(120, 120, 255), curve(Degree::S1, true)),
            ("S3, fine S mesh", RGBColor(255, 120, 120), curve(Degree::S3, true)),
        ];
        crate::plot::lines(&mut chart, series)
    })
}
