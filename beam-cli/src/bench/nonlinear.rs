//! `beam bench nonlinear`: 000 Fig. 10 as a plot and a CSV table: the nonlinear renderer's time on
//! the mirror teapot against scene triangles, S-mesh triangles (beams) and atlas resolution, S1 and
//! S3, beside the ray-traced reference measured in the same run.

use beam_cpu::nonlinear::{render_nonlinear, render_smooth_reference};
use beam_render::nonlinear::Degree;
use beam_render::nonlinear::NonlinearOptions;
use beam_render::options::RenderOptions;
use beam_scene::io::write_atomic;
use beam_scene::scene::Material;
use beam_scene::scene::showcase::mirror_teapot;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One measurement.
struct Row {
    sweep: &'static str,
    x: f64,
    s1: f64,
    s3: f64,
    rays: f64,
    beams: u64,
}

/// The three sweeps: (name, axis label, (teapot n, ball rings, texels) per point, x of each point).
type Sweep = (&'static str, &'static str, Vec<((u32, u32, u32), f64)>);

pub(crate) fn run(size: u32, out: &Path, csv: &Path) -> Result<(), String> {
    let triangles = |n: u32, ball: u32| mirror_teapot(n, ball).triangles.len() as f64;
    let mirror = |n: u32| {
        let s = mirror_teapot(n, 16);
        s.smooth_normals.keys().filter(|&&p| matches!(s.material(p), Material::Mirror { .. })).count() as f64
    };
    let sweeps: Vec<Sweep> = vec![
        (
            "scene triangles",
            "scene triangles",
            [8, 16, 32, 64, 128].iter().map(|&b| ((16, b, 32), triangles(16, b))).collect(),
        ),
        (
            "S-mesh triangles",
            "mirror S-mesh triangles",
            [6, 10, 16, 24, 32].iter().map(|&n| ((n, 16, 32), mirror(n))).collect(),
        ),
        (
            "atlas resolution",
            "most texels per beam side",
            [8, 16, 32, 64, 128].iter().map(|&t| ((16, 16, t), f64::from(t))).collect(),
        ),
    ];
    let points: usize = sweeps.iter().map(|s| s.2.len()).sum();
    let bar = crate::progress::bar(points as u64, "nonlinear sweep");
    let shading = RenderOptions::exact(size, size);
    let mut rows = Vec::new();
    for (name, _, pts) in &sweeps {
        for &((n, ball, texels), x) in pts {
            let scene = mirror_teapot(n, ball);
            let time = |degree| {
                // The eye's beam tree only, as 000 Fig. 10 times it: the area light's caustics
                // (view-independent, made once per light) are left out.
                let options = NonlinearOptions { degree, texels, bounces: 2, caustic_strata: 0, shading };
                let (_, stats) = render_nonlinear(&scene, &options).map_err(|e| e.to_string())?;
                Ok::<_, String>((stats.seconds, stats.beams_per_level.iter().sum::<u64>()))
            };
            let (s1, beams) = time(Degree::S1)?;
            let (s3, _) = time(Degree::S3)?;
            let start = Instant::now();
            let _ = render_smooth_reference(&scene, &shading, 0);
            let rays = start.elapsed().as_secs_f64();
            rows.push(Row { sweep: name, x, s1, s3, rays, beams });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let mut text = String::from("sweep,x,beams,s1_seconds,s3_seconds,rays_seconds\n");
    for r in &rows {
        let _ = writeln!(text, "{},{},{},{:.4},{:.4},{:.4}", r.sweep, r.x, r.beams, r.s1, r.s3, r.rays);
        println!(
            "{:>18} {:>9.0}: {:>6} beams, S1 {:7.3} s, S3 {:7.3} s, rays {:6.3} s (S1/rays {:.0}×)",
            r.sweep,
            r.x,
            r.beams,
            r.s1,
            r.s3,
            r.rays,
            r.s1 / r.rays.max(1e-9)
        );
    }
    write_atomic(csv, text.as_bytes()).map_err(|e| e.to_string())?;
    plot(out, &sweeps, &rows)?;
    println!("wrote {} and {}", out.display(), csv.display());
    Ok(())
}

fn plot(path: &Path, sweeps: &[Sweep], rows: &[Row]) -> Result<(), String> {
    crate::plot::png(path, (1800, 560), |root| {
        for (panel, (name, label, _)) in root.split_evenly((1, 3)).iter().zip(sweeps) {
            let data: Vec<&Row> = rows.iter().filter(|r| r.sweep == *name).collect();
            let (x0, x1) = data.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), r| (lo.min(r.x), hi.max(r.x)));
            let y0 = data.iter().fold(f64::INFINITY, |m, r| m.min(r.rays)).max(1e-4) * 0.5;
            let y1 = data.iter().fold(0.0f64, |m, r| m.max(r.s3).max(r.s1)) * 2.0;
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("time vs {name} (mirror teapot)"), ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d((x0 * 0.9..x1 * 1.1).log_scale(), (y0..y1).log_scale())
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc(*label)
                .y_desc("seconds")
                .x_label_formatter(&|v| format!("{v:.0}"))
                .draw()
                .map_err(|e| e.to_string())?;
            let series = [
                ("nonlinear S1", BLUE, data.iter().map(|r| (r.x, r.s1)).collect::<Vec<_>>()),
                ("nonlinear S3", RED, data.iter().map(|r| (r.x, r.s3)).collect()),
                ("rays (reference)", BLACK, data.iter().map(|r| (r.x, r.rays)).collect()),
            ];
            crate::plot::lines(&mut chart, series.into())?;
        }
        Ok(())
    })
}
