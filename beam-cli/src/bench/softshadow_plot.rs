//! The plot of `beam bench softshadow --sweep light`: seconds against the light's size, log–log,
//! a panel per scene and a line per method.

use super::softshadow_measure::{METHODS, Row};
use plotters::prelude::*;
use std::path::Path;

/// Seconds of each method against the light's edge (fraction of the scene's extent) of the sweep
/// rows of `rows`, a panel per scene, side by side.
pub(super) fn light_sweep(path: &Path, rows: &[Row]) -> Result<(), String> {
    let sweep: Vec<&Row> = rows.iter().filter(|r| r.light.is_some()).collect();
    let mut scenes: Vec<&str> = sweep.iter().map(|r| r.case.as_str()).collect();
    scenes.dedup();
    let seconds = sweep.iter().flat_map(|r| r.seconds.iter().flatten().copied());
    let (y0, y1) = seconds.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v.max(1e-5)), hi.max(v)));
    if scenes.is_empty() || !(y0 <= y1) {
        return Err("no light-sweep rows to plot".into());
    }
    let colors = [BLUE, RGBColor(0, 150, 0), RGBColor(200, 120, 0), RED, MAGENTA];
    crate::plot::png(path, (600 * scenes.len() as u32, 560), |root| {
        for (area, scene) in root.split_evenly((1, scenes.len())).iter().zip(&scenes) {
            let mut chart = ChartBuilder::on(area)
                .caption(format!("{scene}: soft shadows, time vs light size"), ("sans-serif", 22))
                .margin(14)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d((0.007f64..1.4).log_scale(), (y0 * 0.5..y1 * 2.0).log_scale())
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc("light edge / scene extent")
                .y_desc("seconds (median)")
                .x_label_formatter(&|v| format!("{v}"))
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .draw()
                .map_err(|e| e.to_string())?;
            let series = METHODS
                .iter()
                .enumerate()
                .map(|(m, &name)| {
                    let points = sweep
                        .iter()
                        .filter(|r| r.case == *scene)
                        .filter_map(|r| Some((f64::from(r.light?), r.seconds[m]?)))
                        .collect::<Vec<_>>();
                    (name, colors[m], points)
                })
                .filter(|(_, _, p)| !p.is_empty())
                .collect();
            crate::plot::lines(&mut chart, series)?;
        }
        Ok(())
    })
}
