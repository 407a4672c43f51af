//! `beam bench primary --sweep`: eye beams over seeded random views (001 Fig. 7: time against
//! visible triangles). Half the cameras stand inside the scene's box, half outside it in the upper
//! hemisphere around its centre (1.1 to 2 half-diagonals away); each looks at a random point of the
//! box with a 60° field of view. Per camera: eye-beam time and work, our 1 and 16 rays per pixel
//! on the same flat-shaded image, and the budgeted image (eye beams where they cost less than 16
//! rays a pixel, those rays elsewhere: [`Visibility::Budget`]) with its share of exact pixels.

use super::primary::{Loaded, camera, load, ours, ray_image};
use super::primary_shading::flat;
use beam_cpu::render::{Visibility, difference, primary_image};
use beam_math::glam::Vec3;
use beam_scene::io::write_atomic;
use beam_scene::scene::Camera;
use plotters::prelude::*;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use std::path::Path;

/// Cameras and image size per scene unless given: 32 at 256².
pub(crate) const DEFAULTS: (u32, u32) = (32, 256);

/// One camera's measurements.
struct Row {
    scene: String,
    camera: u32,
    inside: bool,
    beam_s: f64,
    visible: u64,
    hit_beams: u64,
    per_visible: f64,
    /// Thread-seconds spent tracing the eye beams (the rest of the work: exact coverage).
    trace_s: f64,
    steps: u64,
    tests: u64,
    pieces: u64,
    ray1_s: f64,
    ray16_s: f64,
    rmse16: f64,
    /// The budgeted image: seconds, share of its pixels by eye beams, RMSE against the exact one.
    budget_s: f64,
    exact_share: f64,
    rmse_budget: f64,
}

/// Rays a pixel of the peer, and of the budgeted image where eye beams do not pay.
const RAYS: u32 = 16;

/// `n` seeded random cameras around the box of `loaded` at `size²`.
fn cameras(loaded: &Loaded, n: u32, size: u32, seed: u64) -> Vec<(bool, Camera)> {
    let b = loaded.scene.bounds();
    let (c, e) = (b.center(), b.extent());
    let mut rng = Pcg32::seed_from_u64(seed);
    let in_box = |rng: &mut Pcg32, margin: f32| {
        b.min + e * Vec3::from_array([0; 3].map(|_| rng.random_range(margin..1.0 - margin)))
    };
    (0..n)
        .map(|i| {
            let inside = i % 2 == 0;
            let position = if inside {
                in_box(&mut rng, 0.05)
            } else {
                let z = rng.random_range(0.0f32..1.0);
                let phi = rng.random_range(0.0..std::f32::consts::TAU);
                let dir = Vec3::new((1.0 - z * z).sqrt() * phi.cos(), z, (1.0 - z * z).sqrt() * phi.sin());
                c + dir * (0.5 * e.length() * rng.random_range(1.1..2.0))
            };
            let target = in_box(&mut rng, 0.0);
            (inside, Camera { position, target, up: Vec3::Y, fov_y: 60.0, width: size, height: size })
        })
        .collect()
}

/// The sweep on each of `scenes`; `cameras_arg` and `size_arg` override the defaults; the plot and
/// a CSV of every camera go to `out` when given.
pub(crate) fn run(
    scenes: &[String],
    cameras_arg: Option<u32>,
    size_arg: Option<u32>,
    seed: u64,
    out: Option<&Path>,
) -> Result<(), String> {
    let mut rows = Vec::new();
    for arg in scenes {
        let Some(loaded) = load(arg)? else { continue };
        let (n, size) = (cameras_arg.unwrap_or(DEFAULTS.0), size_arg.unwrap_or(DEFAULTS.1));
        let scene = &loaded.scene;
        println!("\nsweep {}: {} cameras at {size}×{size} (table view first)", loaded.name, n);
        println!(
            "{:>4} {:>7} {:>9} {:>8} {:>9} {:>8} {:>8} {:>9} {:>9} {:>8} {:>9} {:>9} {:>10} {:>8} {:>9} {:>7} {:>10} {:>8}",
            "cam",
            "where",
            "beams s",
            "visible",
            "hit beams",
            "per vis",
            "trace s",
            "steps",
            "tri tests",
            "pieces",
            "1 ray s",
            "16 rays s",
            "beam/16ray",
            "RMSE 16",
            "budget s",
            "exact %",
            "budg/16ray",
            "RMSE b"
        );
        let bar = crate::progress::bar(u64::from(n) + 1, "sweep");
        let view = camera(&loaded, size);
        let view_inside = beam_math::collide::point_in_aabb(view.position, scene.bounds());
        let views = std::iter::once((view_inside, view)).chain(cameras(&loaded, n, size, seed));
        let first = rows.len();
        for (i, (inside, cam)) in views.enumerate() {
            let (exact, ps) = primary_image(scene, &cam, Visibility::Exact, flat(scene), |_| {});
            let hit = ours(scene);
            let (_, ray1_s) = ray_image(scene, &cam, 1, &hit, &|| {});
            let (img16, ray16_s) = ray_image(scene, &cam, RAYS, &hit, &|| {});
            let (budget, bs) = primary_image(scene, &cam, Visibility::Budget { rays: RAYS }, flat(scene), |_| {});
            let rmse = |img| difference(img, &exact).map(|d| d.rmse).map_err(|e| e.to_string());
            let row = Row {
                scene: loaded.name.clone(),
                camera: i as u32,
                inside,
                beam_s: ps.seconds,
                visible: ps.visible_triangles,
                hit_beams: ps.hit_beams,
                per_visible: ps.hit_beams_per_visible_triangle,
                trace_s: ps.trace_seconds,
                steps: ps.bvh_steps,
                tests: ps.triangle_tests,
                pieces: ps.pieces,
                ray1_s,
                ray16_s,
                rmse16: rmse(&img16)?,
                budget_s: bs.seconds,
                exact_share: 1.0 - bs.ray_pixels as f64 / f64::from(size * size),
                rmse_budget: rmse(&budget)?,
            };
            bar.suspend(|| {
                println!(
                    "{:>4} {:>7} {:>9.4} {:>8} {:>9} {:>8.2} {:>8.4} {:>9} {:>9} {:>8} {:>9.4} {:>9.4} {:>10.2} {:>8.4} {:>9.4} {:>7.1} {:>10.2} {:>8.4}",
                    if i == 0 { "view".to_string() } else { i.to_string() },
                    if inside { "inside" } else { "outside" },
                    row.beam_s,
                    row.visible,
                    row.hit_beams,
                    row.per_visible,
                    row.trace_s,
                    row.steps,
                    row.tests,
                    row.pieces,
                    row.ray1_s,
                    row.ray16_s,
                    row.beam_s / row.ray16_s,
                    row.rmse16,
                    row.budget_s,
                    100.0 * row.exact_share,
                    row.budget_s / row.ray16_s,
                    row.rmse_budget
                );
            });
            bar.inc(1);
            rows.push(row);
        }
        bar.finish_and_clear();
        let worst_median = |f: &dyn Fn(&Row) -> f64| {
            let mut v: Vec<f64> = rows[first..].iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            (v[v.len() - 1], v[v.len() / 2])
        };
        let (tw, tm) = worst_median(&|r| r.beam_s);
        let (rw, rm) = worst_median(&|r| r.beam_s / r.ray16_s);
        let (qw, qm) = worst_median(&|r| r.beam_s / r.ray1_s);
        let (bw, bm) = worst_median(&|r| r.budget_s / r.ray16_s);
        let slower = |f: &dyn Fn(&Row) -> f64| rows[first..].iter().filter(|&r| f(r) > r.ray16_s).count();
        let (es, bs) = (slower(&|r| r.beam_s), slower(&|r| r.budget_s));
        let noisier = rows[first..].iter().filter(|r| r.rmse_budget > r.rmse16).count();
        let (hw, hm) = worst_median(&|r| r.per_visible);
        // Output sensitivity: seconds per visible triangle, over the views that see ≥ 100.
        let per_visible: Vec<f64> =
            rows[first..].iter().filter(|r| r.visible >= 100).map(|r| r.beam_s / r.visible as f64).collect();
        let (sw, sm) = if per_visible.is_empty() {
            (0.0, 0.0)
        } else {
            let mut v = per_visible;
            v.sort_by(f64::total_cmp);
            (v[v.len() - 1], v[v.len() / 2])
        };
        let fit = Fit::of(rows[first..].iter());
        let (worst_fit, worst_cam) = rows[first..]
            .iter()
            .map(|r| (r.beam_s / fit.at(r.visible), r.camera))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap_or((0.0, 0));
        println!(
            "{}: eye beams worst {tw:.4} s, median {tm:.4} s; × 16 rays/pixel worst {rw:.2}, median {rm:.2}; \
             × 1 ray/pixel worst {qw:.2}, median {qm:.2}; hit beams per visible triangle worst {hw:.1}, median \
             {hm:.1}; µs per visible triangle (views seeing ≥ 100) worst {:.1}, median {:.1}",
            loaded.name,
            sw * 1e6,
            sm * 1e6
        );
        println!(
            "{}: slower than {RAYS} rays/pixel: eye beams on {es} of {n1} views, budgeted on {bs} (× {RAYS} rays \
             worst {bw:.2}, median {bm:.2}); budgeted RMSE above the rays' on {noisier}",
            loaded.name,
            n1 = rows.len() - first
        );
        println!(
            "{}: least-squares line t = {:.4} s + {:.2} µs × visible triangles; slowest view against it: \
             {worst_fit:.2}× (camera {})",
            loaded.name,
            fit.a,
            fit.b * 1e6,
            if worst_cam == 0 { "view".to_string() } else { worst_cam.to_string() }
        );
    }
    if let (Some(dir), false) = (out, rows.is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let mut csv = String::from("scene,camera,inside,beam_s,visible_triangles,hit_beams,hit_beams_per_visible,");
        csv.push_str(
            "trace_s,bvh_steps,triangle_tests,pieces,ray1_s,ray16_s,rmse16,budget_s,exact_share,rmse_budget\n",
        );
        for r in &rows {
            csv.push_str(&format!(
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                r.scene,
                r.camera,
                r.inside,
                r.beam_s,
                r.visible,
                r.hit_beams,
                r.per_visible,
                r.trace_s,
                r.steps,
                r.tests,
                r.pieces,
                r.ray1_s,
                r.ray16_s,
                r.rmse16,
                r.budget_s,
                r.exact_share,
                r.rmse_budget
            ));
        }
        let (png, csv_path) = (dir.join("primary-sweep.png"), dir.join("primary-sweep.csv"));
        write_atomic(&csv_path, csv.as_bytes()).map_err(|e| e.to_string())?;
        plot(&png, &rows)?;
        println!("wrote {} and {}", png.display(), csv_path.display());
    }
    Ok(())
}

/// The least-squares line through the views' (visible triangles, eye-beam seconds): what an
/// output-sensitive method's time should follow (001 Fig. 7). Its intercept is kept ≥ 0.1 ms so
/// that views seeing nothing are not measured against zero.
struct Fit {
    a: f64,
    b: f64,
}

impl Fit {
    fn of<'r>(rows: impl Iterator<Item = &'r Row> + Clone) -> Self {
        let n = rows.clone().count().max(1) as f64;
        let mx = rows.clone().map(|r| r.visible as f64).sum::<f64>() / n;
        let my = rows.clone().map(|r| r.beam_s).sum::<f64>() / n;
        let sxx: f64 = rows.clone().map(|r| (r.visible as f64 - mx).powi(2)).sum();
        let sxy: f64 = rows.map(|r| (r.visible as f64 - mx) * (r.beam_s - my)).sum();
        let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
        Self { a: (my - b * mx).max(1e-4), b }
    }

    /// Seconds the line gives for `visible` triangles.
    fn at(&self, visible: u64) -> f64 {
        self.at_f(visible as f64)
    }

    fn at_f(&self, visible: f64) -> f64 {
        self.a + self.b * visible
    }
}

/// Time against visible triangles, log–log: eye beams filled circles, the budgeted image filled
/// triangles, 16 rays per pixel hollow circles, a colour per scene.
fn plot(path: &Path, rows: &[Row]) -> Result<(), String> {
    let fold = |f: &dyn Fn(&Row) -> f64| {
        rows.iter().map(f).fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)))
    };
    let (x0, x1) = fold(&|r| r.visible.max(1) as f64);
    let (y0, y1) = fold(&|r| r.beam_s.min(r.ray16_s).min(r.budget_s).max(1e-5));
    let (_, y1b) = fold(&|r| r.beam_s.max(r.ray16_s));
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    crate::plot::png(path, (1000, 700), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption("eye beams: time vs visible triangles (random views)", ("sans-serif", 24))
            .margin(14)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x0 * 0.7..x1 * 1.4).log_scale(), (y0 * 0.5..y1.max(y1b) * 2.0).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("visible triangles")
            .y_desc("seconds")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| e.to_string())?;
        let palette = [BLUE, RED, RGBColor(0, 150, 0), MAGENTA, RGBColor(200, 120, 0), CYAN];
        for (k, name) in scenes.iter().enumerate() {
            let color = palette[k % palette.len()];
            let pts = |f: fn(&Row) -> f64| -> Vec<(f64, f64)> {
                rows.iter().filter(|r| r.scene == *name).map(|r| (r.visible.max(1) as f64, f(r))).collect()
            };
            chart
                .draw_series(pts(|r| r.beam_s).into_iter().map(|p| Circle::new(p, 5, color.filled())))
                .map_err(|e| e.to_string())?
                .label(format!("{name}: eye beams (exact)"))
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
            chart
                .draw_series(pts(|r| r.budget_s).into_iter().map(|p| TriangleMarker::new(p, 6, color.filled())))
                .map_err(|e| e.to_string())?
                .label(format!("{name}: budgeted (eye beams, rays where they do not pay)"))
                .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 6, color.filled()));
            chart
                .draw_series(pts(|r| r.ray16_s).into_iter().map(|p| Circle::new(p, 5, color.stroke_width(2))))
                .map_err(|e| e.to_string())?
                .label(format!("{name}: 16 rays/pixel"))
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.stroke_width(2)));
            let fit = Fit::of(rows.iter().filter(|r| r.scene == *name));
            let line = (0..=64).map(|i| {
                let v = x0 * 0.7 * (x1 * 2.0 / x0).powf(f64::from(i) / 64.0);
                (v, fit.at_f(v))
            });
            chart
                .draw_series(LineSeries::new(line, color.stroke_width(1)))
                .map_err(|e| e.to_string())?
                .label(format!("{name}: least-squares line"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())
    })
}
