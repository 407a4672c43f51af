//! Reproduction of 000 Fig. 7: the pixel overdraw ratio (bounding-triangle area over the true area
//! of the projection) of one scene triangle rendered in one diverging S1 beam, for our bounding
//! triangle (Alg. 3) and for the general case alone (the algorithm of \[11\]), sweeping the triangle's
//! size at a fixed distance and its distance at a fixed size.

use beam_math::Triangle;
use beam_math::collide::WatertightRay;
use beam_math::glam::Vec3;
use beam_math::nonlinear::{BeamBounds, BoundingCase, BoundingTriangle, NonlinearBeam};

/// Which quantity a sweep varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// Triangle size at a fixed distance (Fig. 7 left).
    Size,
    /// Distance from the beam base at a fixed size (Fig. 7 right).
    Distance,
}

impl Sweep {
    /// Column label.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Sweep::Size => "size",
            Sweep::Distance => "distance",
        }
    }
}

/// One point of a sweep.
#[derive(Clone, Copy, Debug)]
pub struct OverdrawRow {
    /// The sweep this row belongs to.
    pub sweep: Sweep,
    /// Triangle circumradius (size sweep) or ray parameter of its centre (distance sweep).
    pub parameter: f32,
    /// True projected area over the base area.
    pub true_area: f64,
    /// Our overdraw ratio (Alg. 3): bounding-triangle area over true projected area.
    pub ours: f64,
    /// Branch of Alg. 3 that produced our bounding triangle.
    pub ours_case: BoundingCase,
    /// Overdraw ratio of the general case alone (\[11\]).
    pub general: f64,
    /// Our overdraw with the bounding triangle clipped to the base triangle.
    pub ours_clipped: f64,
    /// The general case's overdraw clipped to the base triangle.
    pub general_clipped: f64,
}

/// The beam of the experiment: a diverging S1 beam over a unit-size base, as off a convex mirror.
#[must_use]
pub fn experiment_beam() -> NonlinearBeam {
    let base = [Vec3::new(-0.5, -0.29, 0.0), Vec3::new(0.5, -0.29, 0.0), Vec3::new(0.0, 0.58, 0.0)];
    let c = (base[0] + base[1] + base[2]) / 3.0;
    let dirs = base.map(|p| (Vec3::Z + 0.6 * (p - c)).normalize());
    NonlinearBeam::s1(base, dirs).expect("valid experiment beam")
}

/// The scene triangle: equilateral with circumradius `size`, centred on the central ray at
/// parameter `distance`, facing the base.
#[must_use]
pub fn experiment_triangle(beam: &NonlinearBeam, size: f32, distance: f32) -> Triangle {
    let ray = beam.ray_at(Vec3::splat(1.0 / 3.0));
    let c = ray.at(distance);
    let n = ray.direction.normalize();
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let corner = |a: f32| c + size * (a.cos() * u + a.sin() * v);
    let third = std::f32::consts::TAU / 3.0;
    Triangle::new(corner(0.3), corner(0.3 + third), corner(0.3 + 2.0 * third))
}

/// Fraction of a bounding triangle whose rays hit `tri`, on a barycentric grid of `n` steps.
fn hit_fraction(beam: &NonlinearBeam, bt: &BoundingTriangle, tri: &Triangle, n: usize) -> f64 {
    let corners = bt.corners();
    let (mut hits, mut total) = (0u64, 0u64);
    // Sample cell centres of the grid (avoids counting edges twice).
    for i in 0..n {
        for j in 0..n - i {
            for (a, b) in [(i as f32 + 1.0 / 3.0, j as f32 + 1.0 / 3.0), (i as f32 + 2.0 / 3.0, j as f32 + 2.0 / 3.0)] {
                if a + b > n as f32 {
                    continue;
                }
                let (x, y) = (a / n as f32, b / n as f32);
                let w = corners[0] * (1.0 - x - y) + corners[1] * x + corners[2] * y;
                total += 1;
                if w.min_element() < 0.0 {
                    continue;
                }
                if WatertightRay::new(beam.ray_at(w)).intersect(tri, 0.0, f32::INFINITY).is_some() {
                    hits += 1;
                }
            }
        }
    }
    hits as f64 / total.max(1) as f64
}

/// One measurement: both bounding triangles and the true area, measured inside our (conservative)
/// bounding triangle so that even tiny projections are sampled densely.
#[must_use]
pub fn measure(
    beam: &NonlinearBeam,
    bounds: &BeamBounds,
    tri: &Triangle,
    sweep: Sweep,
    parameter: f32,
) -> Option<OverdrawRow> {
    let ours = beam.bounding_triangle(bounds, tri)?;
    let general = beam.bounding_triangle_general(bounds, tri)?;
    let fraction = hit_fraction(beam, &ours, tri, 300);
    if fraction == 0.0 {
        return None;
    }
    let true_area = fraction * f64::from(ours.area_ratio());
    Some(OverdrawRow {
        sweep,
        parameter,
        true_area,
        ours: f64::from(ours.area_ratio()) / true_area,
        ours_case: ours.case,
        general: f64::from(general.area_ratio()) / true_area,
        ours_clipped: f64::from(ours.clipped_area_ratio()) / true_area,
        general_clipped: f64::from(general.clipped_area_ratio()) / true_area,
    })
}

/// `count` values from `lo` to `hi`, evenly spaced in log scale.
fn log_space(lo: f32, hi: f32, count: usize) -> impl Iterator<Item = f32> {
    (0..count).map(move |i| lo * (hi / lo).powf(i as f32 / (count - 1) as f32))
}

/// Both sweeps of Fig. 7: size from 0.02 to 2 at distance 10, distance from 0.5 to 200 at size 0.1.
/// `progress` is called after each point.
pub fn sweep(points: usize, mut progress: impl FnMut()) -> Vec<OverdrawRow> {
    let beam = experiment_beam();
    let bounds = beam.bounds();
    let mut rows = Vec::new();
    for size in log_space(0.02, 2.0, points) {
        rows.extend(measure(&beam, &bounds, &experiment_triangle(&beam, size, 10.0), Sweep::Size, size));
        progress();
    }
    for distance in log_space(0.5, 200.0, points) {
        rows.extend(measure(&beam, &bounds, &experiment_triangle(&beam, 0.1, distance), Sweep::Distance, distance));
        progress();
    }
    rows
}

/// The rows as CSV.
#[must_use]
pub fn to_csv(rows: &[OverdrawRow]) -> String {
    let mut s = String::from(
        "sweep,parameter,true_area_over_base,ours_overdraw,ours_case,general_overdraw,ours_clipped_overdraw,general_clipped_overdraw\n",
    );
    for r in rows {
        s += &format!(
            "{},{},{:.6e},{:.4},{:?},{:.4},{:.4},{:.4}\n",
            r.sweep.name(),
            r.parameter,
            r.true_area,
            r.ours,
            r.ours_case,
            r.general,
            r.ours_clipped,
            r.general_clipped
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ours_stays_flat_where_the_general_case_grows() {
        let rows = sweep(6, || {});
        let dist: Vec<_> = rows.iter().filter(|r| r.sweep == Sweep::Distance).collect();
        assert!(dist.len() >= 5);
        let (first, last) = (dist.first().unwrap(), dist.last().unwrap());
        assert!(last.general > 20.0 * first.general, "general {} → {}", first.general, last.general);
        for r in &rows {
            assert!(r.ours >= 0.99, "a conservative bounding triangle has overdraw ≥ 1: {r:?}");
            assert!(r.ours <= r.general * 1.0001, "ours never worse than the general case: {r:?}");
        }
        let far: Vec<_> = dist.iter().filter(|r| r.parameter > 2.0).collect();
        let (lo, hi) = far.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), r| (lo.min(r.ours), hi.max(r.ours)));
        assert!(hi < 3.0 * lo, "ours roughly constant: {lo}..{hi}");
    }
}
