//! Polygon beams (001 §3.2): the split is exact.

use crate::generate::{self, uniform};
use crate::property::{Backend, Config, Outcome};
use beam_math::collide::{ConvexPolygon, ray_triangle};
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, PolyBeam};
use beam_math::{Ray, Triangle};
use rand::Rng;

/// Distance from `p` to the boundary of a convex polygon.
fn boundary_distance(p: Vec2, poly: &[Vec2]) -> f32 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            p.distance(a + t * (b - a))
        })
        .fold(f32::INFINITY, f32::min)
}

/// Splitting a random 3- or 4-corner beam by a random triangle (2,000 pairs): hit and miss areas sum
/// to the beam's area; the hit area equals the overlap of the beam with the triangle's projection
/// (004 App. A.9) when the triangle lies in front; and for 500 random rays per pair, a ray hits the
/// triangle exactly when it lies in a hit piece (except within 1e-4 of an edge).
pub(super) fn polybeam_split_is_exact(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(13);
    let (mut rays, mut partial) = (0u64, 0u64);
    let n = 2_000;
    for i in 0..n {
        let apex = generate::point(&mut rng, 2.0);
        let normal = generate::unit(&mut rng);
        let frame = BeamFrame::new(apex, apex + normal * uniform(&mut rng, 0.5, 2.0), normal, generate::unit(&mut rng))
            .ok_or("frame")?;
        let corners = rng.random_range(3..=4);
        let section = generate::convex_polygon(&mut rng, Vec2::ZERO, 1.0);
        let pts: Vec<Vec3> = section.vertices().iter().take(corners.max(3)).map(|&c| frame.point(c)).collect();
        let Some(beam) = PolyBeam::new(frame, &pts) else {
            continue;
        };
        let center =
            frame.ray(generate::convex_polygon(&mut rng, Vec2::ZERO, 0.5).centroid()).at(uniform(&mut rng, 0.5, 4.0));
        let size = uniform(&mut rng, 0.3, 4.0);
        let tri = Triangle::new(
            center + size * generate::point(&mut rng, 1.0),
            center + size * generate::point(&mut rng, 1.0),
            center + size * generate::point(&mut rng, 1.0),
        );
        let split = beam.split(&tri, 1e-3, f32::INFINITY, 1e-6).map_err(|e| format!("case {i}: {e:?}"))?;
        let total = split.hit.area() + split.miss.area();
        if (total - beam.area()).abs() > 1e-4 * beam.area().max(1.0) {
            return Err(format!("case {i}: pieces cover {total} of {}", beam.area()));
        }
        partial += u64::from(!split.hit.is_empty() && !split.miss.is_empty());
        let in_front = tri.v.iter().all(|&p| frame.depth(p) > 1e-3);
        let projected: Vec<Vec2> = tri.v.iter().map(|&p| frame.project(p)).collect();
        if in_front {
            let proj = ConvexPolygon::<16>::from_slice(&projected).map_err(|e| format!("{e:?}"))?;
            let overlap = beam.section.intersect(&proj).map_err(|e| format!("{e:?}"))?.area();
            if (overlap - split.hit.area()).abs() > 1e-3 * beam.area().max(1.0) {
                return Err(format!("case {i}: hit area {} vs overlap {overlap}", split.hit.area()));
            }
        }
        let lo = beam.section.vertices().iter().fold(Vec2::INFINITY, |m, v| m.min(*v));
        let hi = beam.section.vertices().iter().fold(Vec2::NEG_INFINITY, |m, v| m.max(*v));
        for _ in 0..500 {
            let c = Vec2::new(uniform(&mut rng, lo.x, hi.x), uniform(&mut rng, lo.y, hi.y));
            if !beam_math::collide::point_in_convex_polygon(c, beam.section.vertices()) {
                continue;
            }
            rays += 1;
            let ray: Ray = frame.ray(c);
            let hits = ray_triangle(ray, &tri).is_some_and(|h| h.t >= 1e-3);
            let in_hit = split.hit.iter().any(|s| beam_math::collide::point_in_convex_polygon(c, s.vertices()));
            if hits != in_hit {
                let near_edge = boundary_distance(c, &projected) < 1e-4
                    || split.hit.iter().chain(split.miss.iter()).any(|s| boundary_distance(c, s.vertices()) < 1e-4);
                if !near_edge {
                    return Err(format!("case {i}: ray through {c} hits={hits} but in hit piece={in_hit}"));
                }
            }
        }
    }
    Ok(Outcome { cases: n, note: format!("{partial} partial splits, {rays} rays agree with their pieces") })
}
