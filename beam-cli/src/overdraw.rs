//! `beam overdraw`: 000 Fig. 7 as a plot and a CSV table.

use beam_cpu::overdraw::{OverdrawRow, Sweep, sweep, to_csv};
use beam_scene::io::write_atomic;
use plotters::prelude::*;
use std::path::Path;
use std::process::ExitCode;

pub(crate) fn run(out: &Path, csv: &Path, points: usize) -> Result<ExitCode, String> {
    if points < 2 {
        return Err("--points must be at least 2".into());
    }
    let bar = crate::progress::bar(2 * points as u64, "overdraw");
    let rows = sweep(points, || bar.inc(1));
    bar.finish_and_clear();
    write_atomic(csv, to_csv(&rows).as_bytes()).map_err(|e| e.to_string())?;
    plot(out, &rows)?;
    for s in [Sweep::Size, Sweep::Distance] {
        let (ours, general) = range(&rows, s);
        println!(
            "{} sweep: ours {:.2}..{:.2} (max/min {:.1}), general case {:.2}..{:.1} (max/min {:.0})",
            s.name(),
            ours.0,
            ours.1,
            ours.1 / ours.0,
            general.0,
            general.1,
            general.1 / general.0
        );
    }
    println!("wrote {} and {}", out.display(), csv.display());
    Ok(ExitCode::SUCCESS)
}

/// (min, max) of ours and of the general case over one sweep.
fn range(rows: &[OverdrawRow], s: Sweep) -> ((f64, f64), (f64, f64)) {
    let mm = |f: fn(&OverdrawRow) -> f64| {
        rows.iter().filter(|r| r.sweep == s).map(f).fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)))
    };
    (mm(|r| r.ours), mm(|r| r.general))
}

fn plot(path: &Path, rows: &[OverdrawRow]) -> Result<(), String> {
    crate::plot::png(path, (1400, 560), |root| {
        let panels = root.split_evenly((1, 2));
        for (panel, s) in panels.iter().zip([Sweep::Size, Sweep::Distance]) {
            let data: Vec<_> = rows.iter().filter(|r| r.sweep == s).collect();
            let (x0, x1) =
                data.iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), r| (lo.min(r.parameter), hi.max(r.parameter)));
            let y1 = data.iter().fold(1.0f64, |m, r| m.max(r.general)) * 2.0;
            let (title, xlabel) = match s {
                Sweep::Size => ("fixed distance, varying triangle size", "triangle circumradius"),
                Sweep::Distance => ("fixed size, varying distance to beam base", "distance along the central ray"),
            };
            let mut chart = ChartBuilder::on(panel)
                .caption(title, ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(80)
                .build_cartesian_2d((x0..x1).log_scale(), (0.8f64..y1).log_scale())
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc(xlabel)
                .y_desc("overdraw ratio")
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .x_label_formatter(&|v| format!("{v}"))
                .draw()
                .map_err(|e| e.to_string())?;
            let series = [
                ("general case only ([11])", RED, data.iter().map(|r| (r.parameter, r.general)).collect::<Vec<_>>()),
                ("ours (Alg. 3)", BLUE, data.iter().map(|r| (r.parameter, r.ours)).collect()),
            ];
            crate::plot::lines(&mut chart, series.into())?;
        }
        Ok(())
    })
}
