//! Nonlinear beams (000 §4–6): projection, threshold plane, bounding triangles and cones.

use crate::generate::{self, BeamKind, Rng64, barycentric_grid, uniform};
use crate::property::{Backend, Config, Outcome};
use beam_math::Triangle;
use beam_math::collide::WatertightRay;
use beam_math::glam::{DMat3, Vec2, Vec3};
use beam_math::nonlinear::{BeamBounds, BoundingCase, BoundingTriangle, BumpBeam, Interpolant, NonlinearBeam};

/// Containment tolerance in barycentric coordinates.
const TOL: f32 = 1e-4;

/// Condition of the projection at `(w, t)`: `‖J⁻¹‖` of `(ω1, ω2, t) ↦ O(ω) + t·d(ω)`, large near a
/// fold of the beam (a caustic), where a rounding of `Q` moves or annihilates its preimages.
fn inverse_jacobian_norm<L: Interpolant>(beam: &NonlinearBeam<L>, w: Vec3, t: f32) -> f64 {
    let w = w.as_dvec3();
    let t = f64::from(t);
    let [(o1, d1), (o2, d2)] = beam.patch.derivatives(w);
    let (_, d) = beam.patch.eval(w);
    let j = DMat3::from_cols(o1 + t * d1, o2 + t * d2, d);
    if j.determinant() == 0.0 {
        return f64::INFINITY;
    }
    let inv = j.inverse();
    (inv.x_axis.length_squared() + inv.y_axis.length_squared() + inv.z_axis.length_squared()).sqrt()
}

/// `Q = O_P + t·d_P` for random base points and `t`, S1 and S3, diverging, converging and mixed
/// beams: projection returns `(P, t)` among its solutions, and every solution maps back to `Q`.
/// Samples where the f32 rounding of `Q` can move the preimage by more than the tolerance (at a
/// fold, `‖J⁻¹‖·|δQ| > 2e-3`) are counted as ill-conditioned instead.
pub(super) fn projection_inverts_intersection(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(7);
    let (mut cases, mut ill) = (0u64, 0u64);
    let mut worst = 0.0f32;
    for kind in BeamKind::ALL {
        for b in 0..150 {
            let s1 = generate::s1_beam(&mut rng, kind);
            let s3 = generate::s3_beam(&mut rng, kind);
            for k in 0..20 {
                let w = generate::barycentric(&mut rng);
                let t = uniform(&mut rng, 0.05, 20.0);
                let mut check = |name: &str,
                                 pairs: Vec<(Vec3, f32)>,
                                 q: Vec3,
                                 back: &dyn Fn(Vec3, f32) -> Vec3,
                                 cond: f64|
                 -> Result<(), String> {
                    cases += 1;
                    for &(w2, t2) in &pairs {
                        let err = (back(w2, t2) - q).length() / (1.0 + t);
                        worst = worst.max(err);
                        if err > 1e-3 {
                            return Err(format!(
                                "{name} {kind:?} beam {b}: projection (ω={w2}, t={t2}) maps to a point {err} away"
                            ));
                        }
                    }
                    let found = pairs
                        .iter()
                        .any(|&(w2, t2)| (w2 - w).abs().max_element() < 2e-3 && (t2 - t).abs() < 2e-3 * (1.0 + t));
                    if !found {
                        if cond * 1e-5 * f64::from(1.0 + q.length()) > 2e-3 {
                            ill += 1;
                            return Ok(());
                        }
                        return Err(format!(
                            "{name} {kind:?} beam {b} sample {k}: (ω={w}, t={t}) not among {pairs:?} (‖J⁻¹‖ = {cond:.1})"
                        ));
                    }
                    Ok(())
                };
                let q = s1.ray_at(w).at(t);
                let pairs = s1.project(q).iter().map(|p| (p.bary, p.t)).collect();
                check("S1", pairs, q, &|w, t| s1.ray_at(w).at(t), inverse_jacobian_norm(&s1, w, t))?;
                let q = s3.ray_at(w).at(t);
                let pairs = s3.project(q).iter().map(|p| (p.bary, p.t)).collect();
                check("S3", pairs, q, &|w, t| s3.ray_at(w).at(t), inverse_jacobian_norm(&s3, w, t))?;
            }
        }
    }
    Ok(Outcome {
        cases,
        note: format!("max |O + t·d − Q| / (1 + t) = {worst:.1e}; {ill} ill-conditioned samples (at folds) skipped"),
    })
}

/// Claim B.3: a point inside an S1 beam and above its threshold plane has exactly one projection
/// in the base triangle (30,000 points over 1,500 beams of every kind).
pub(super) fn threshold_plane_unique_projection(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(8);
    let (mut above, mut cases) = (0u64, 0u64);
    for kind in BeamKind::ALL {
        for b in 0..500 {
            let beam = generate::s1_beam(&mut rng, kind);
            let th = beam.threshold_plane();
            for _ in 0..20 {
                let w = generate::barycentric(&mut rng);
                let t = uniform(&mut rng, 0.0, 2.0 * th.t_res.min(50.0) + 10.0);
                let q = beam.ray_at(w).at(t);
                cases += 1;
                if th.plane.eval(q) > 1e-3 {
                    above += 1;
                    let n = beam.project(q).iter().filter(|p| p.t >= 0.0).count();
                    if n != 1 {
                        return Err(format!(
                            "{kind:?} beam {b}: point at (ω={w}, t={t}) above Π_T (t_res={}) has {n} projections",
                            th.t_res
                        ));
                    }
                }
            }
        }
    }
    Ok(Outcome { cases, note: format!("{above} points above Π_T, each with one projection") })
}

/// Counts of each branch and the largest containment violation found.
#[derive(Default)]
struct Tally {
    cases: u64,
    brute: u64,
    general: u64,
    unique: u64,
    culled: u64,
    checked_points: u64,
}

impl Tally {
    fn add(&mut self, b: Option<BoundingTriangle>) {
        self.cases += 1;
        match b.map(|b| b.case) {
            None => self.culled += 1,
            Some(BoundingCase::BruteForce) => self.brute += 1,
            Some(BoundingCase::General) => self.general += 1,
            Some(BoundingCase::UniqueProjection) => self.unique += 1,
        }
    }

    fn outcome(&self) -> Outcome {
        Outcome {
            cases: self.cases,
            note: format!(
                "{} points checked; cases: {} unique-projection, {} general, {} brute force, {} culled",
                self.checked_points, self.unique, self.general, self.brute, self.culled
            ),
        }
    }
}

/// Every base point whose ray (from `ray`) hits `tri` at `t ≥ 0` lies in the bounding triangle.
fn check_by_rays(
    bt: Option<BoundingTriangle>,
    tri: &Triangle,
    ray: &dyn Fn(Vec3) -> beam_math::Ray,
    grid: usize,
    tally: &mut Tally,
) -> Result<(), String> {
    for w in barycentric_grid(grid) {
        let r = ray(w);
        if WatertightRay::new(r).intersect(tri, 0.0, f32::INFINITY).is_some() {
            tally.checked_points += 1;
            match bt {
                Some(b) if b.contains(w, TOL) => {}
                _ => {
                    return Err(format!("base point ω={w} sees the triangle but lies outside {bt:?}"));
                }
            }
        }
    }
    Ok(())
}

/// Every projection (with `t ≥ 0`) of sampled points of `tri` lies in the bounding triangle.
fn check_by_projection<L: Interpolant>(
    beam: &NonlinearBeam<L>,
    bt: Option<BoundingTriangle>,
    tri: &Triangle,
    grid: usize,
    tally: &mut Tally,
) -> Result<(), String> {
    for w in barycentric_grid(grid) {
        let q = tri.point(w);
        for p in beam.project(q).iter().filter(|p| p.t >= 0.0) {
            tally.checked_points += 1;
            match bt {
                Some(b) if b.contains(p.bary, TOL) => {}
                _ => {
                    return Err(format!("point {q} projects to ω={} (t={}) outside {bt:?}", p.bary, p.t));
                }
            }
        }
    }
    Ok(())
}

fn bounding_triangle_property<L: Interpolant>(
    seed: u64,
    beams: usize,
    make: fn(&mut Rng64, BeamKind) -> NonlinearBeam<L>,
    projection_grid: usize,
) -> Result<Outcome, String> {
    let mut rng = generate::rng(seed);
    let mut tally = Tally::default();
    for kind in BeamKind::ALL {
        for b in 0..beams {
            let beam = make(&mut rng, kind);
            let bounds: BeamBounds = beam.bounds();
            for k in 0..40 {
                let tri = generate::scene_triangle(&mut rng, &beam);
                let bt = beam.bounding_triangle(&bounds, &tri);
                tally.add(bt);
                let context = |e: String| {
                    format!(
                        "{kind:?} beam {b} triangle {k}: {e}\nbeam {:?} {:?}\ntriangle {:?}",
                        beam.base, beam.dirs, tri.v
                    )
                };
                check_by_rays(bt, &tri, &|w| beam.ray_at(w), 24, &mut tally).map_err(context)?;
                check_by_projection(&beam, bt, &tri, projection_grid, &mut tally).map_err(context)?;
            }
        }
    }
    Ok(tally.outcome())
}

/// S1 bounding triangles (Alg. 3) contain the projection of every sampled point of their scene
/// triangle, and every base point whose ray hits it: 18,000 (beam, triangle) pairs over diverging,
/// converging and mixed beams.
pub(super) fn bounding_triangle_s1(_: Backend, _: &Config) -> Result<Outcome, String> {
    bounding_triangle_property(9, 150, generate::s1_beam, 10)
}

/// S3 bounding triangles (Alg. 4, extremal directions and ε-expansion): as for S1, 6,000 pairs.
pub(super) fn bounding_triangle_s3(_: Backend, _: &Config) -> Result<Outcome, String> {
    bounding_triangle_property(10, 50, generate::s3_beam, 3)
}

/// A bump map's tilt field: high-frequency, magnitude up to 1.
fn tilt(w: Vec3) -> Vec2 {
    Vec2::new((17.0 * w.x + 5.0 * w.y).sin(), (13.0 * w.y - 7.0 * w.z).cos()) * std::f32::consts::FRAC_1_SQRT_2
}

/// Bump-map bounding triangles (eq. 5, D-expansion) contain every base point whose perturbed ray
/// hits the scene triangle: 9,000 pairs, δ between 0.01 and 0.15 rad.
pub(super) fn bounding_triangle_bump(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(11);
    let mut tally = Tally::default();
    for kind in BeamKind::ALL {
        for b in 0..75 {
            let beam = BumpBeam { beam: generate::s1_beam(&mut rng, kind), delta: uniform(&mut rng, 0.01, 0.15) };
            let bounds = beam.beam.bounds();
            for k in 0..40 {
                let tri = generate::scene_triangle(&mut rng, &beam.beam);
                let bt = beam.bounding_triangle(&bounds, &tri);
                tally.add(bt);
                check_by_rays(bt, &tri, &|w| beam.ray_at(w, tilt(w)), 24, &mut tally)
                    .map_err(|e| format!("{kind:?} beam {b} (δ={}) triangle {k}: {e}", beam.delta))?;
            }
        }
    }
    Ok(tally.outcome())
}

/// The bounding cone (000 App. A) contains sampled points of S1, S3 and bump beams.
pub(super) fn bounding_cone_contains_beam(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(12);
    let mut cases = 0u64;
    for kind in BeamKind::ALL {
        for b in 0..300 {
            let s1 = generate::s1_beam(&mut rng, kind);
            let s3 = generate::s3_beam(&mut rng, kind);
            let bump = BumpBeam { beam: s1, delta: uniform(&mut rng, 0.01, 0.2) };
            let cones = [
                s1.bounding_cone(&s1.dirs, 0.0),
                s3.bounding_cone(&s3.extremal_directions(), 0.0),
                bump.bounding_cone(),
            ];
            for _ in 0..30 {
                let w = generate::barycentric(&mut rng);
                let t = uniform(&mut rng, 0.0, 30.0);
                let points = [s1.ray_at(w).at(t), s3.ray_at(w).at(t), {
                    let r = bump.ray_at(w, tilt(w));
                    r.at(t)
                }];
                for (i, (cone, p)) in cones.iter().zip(points).enumerate() {
                    cases += 1;
                    if !cone.contains(p) {
                        return Err(format!("{kind:?} beam {b}: point {p} (ω={w}, t={t}) outside cone {i} {cone:?}"));
                    }
                }
            }
        }
    }
    Ok(Outcome { cases, note: "S1, S3 and bump cones all conservative".into() })
}
