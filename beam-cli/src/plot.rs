//! What the benchmark plots share: a PNG canvas and labelled lines with dots and a legend.

use beam_scene::io::write_png;
use plotters::coord::Shift;
use plotters::coord::ranged1d::Ranged;
use plotters::prelude::*;
use std::path::Path;

/// A `w × h` white canvas handed to `draw`, then written to `path` as PNG (atomically).
pub(crate) fn png(
    path: &Path,
    (w, h): (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<(), String> {
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        draw(&root)?;
        root.present().map_err(|e| e.to_string())?;
    }
    write_png(path, w, h, &buf).map_err(|e| e.to_string())
}

/// A labelled series: legend label, colour, points.
pub(crate) type Series<'s, X, Y> = (&'s str, RGBColor, Vec<(X, Y)>);

/// Each series as a line with a dot at every point, and the legend in the upper left.
pub(crate) fn lines<'a, X, Y>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<X, Y>>,
    series: Vec<Series<'_, X::ValueType, Y::ValueType>>,
) -> Result<(), String>
where
    X: Ranged,
    Y: Ranged,
    X::ValueType: Copy + 'static,
    Y::ValueType: Copy + 'static,
{
    for (label, color, points) in series {
        chart
            .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled()))).map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())
}
