//! Triangulating an OBJ face: a polygon of any number of corners, convex or not, split into
//! triangles that cover exactly the polygon seen along its best-fit (Newell) normal.

use super::limits::MAX_NONCONVEX_CORNERS;
use crate::error::FaceError;
use beam_math::glam::{DVec2, DVec3, Vec3};

/// Triangles of the polygon `corners` (indices into `positions`, in order), keeping its winding:
/// a fan for a triangle or a convex polygon, ear clipping in the polygon's best-fit plane for a
/// simple non-convex one. Corners on a straight edge add no triangle. A polygon that crosses
/// itself (seen along its normal) is an error; so is a non-convex one of more than
/// [`MAX_NONCONVEX_CORNERS`] corners. A polygon with non-finite corners or no area is fanned
/// (its triangles are degenerate, filtered and counted later).
pub fn triangulate(positions: &[Vec3], corners: &[u32], out: &mut Vec<[u32; 3]>) -> Result<(), FaceError> {
    let n = corners.len();
    let fan = |out: &mut Vec<[u32; 3]>| out.extend((1..n - 1).map(|i| [corners[0], corners[i], corners[i + 1]]));
    if n == 3 {
        out.push([corners[0], corners[1], corners[2]]);
        return Ok(());
    }
    let p3: Vec<DVec3> = corners.iter().map(|&i| positions[i as usize].as_dvec3()).collect();
    // Newell's normal: the polygon's vector area, exact for planar polygons, best fit otherwise.
    // A polygon whose lobes cancel (a bow tie) has none: then the largest fan triangle's normal.
    let newell = (0..n).fold(DVec3::ZERO, |s, i| s + p3[i].cross(p3[(i + 1) % n]));
    let largest = || {
        (1..n - 1)
            .map(|i| (p3[i] - p3[0]).cross(p3[i + 1] - p3[0]))
            .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
    };
    let Some(normal) = newell.try_normalize().or_else(|| largest().and_then(DVec3::try_normalize)) else {
        fan(out);
        return Ok(());
    };
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let origin = p3[0];
    let mut p: Vec<DVec2> = p3.iter().map(|&q| DVec2::new((q - origin).dot(u), (q - origin).dot(v))).collect();
    if (0..n).map(|i| p[i].perp_dot(p[(i + 1) % n])).sum::<f64>() < 0.0 {
        p.iter_mut().for_each(|q| q.y = -q.y);
    }
    if is_convex(&p) {
        fan(out);
        return Ok(());
    }
    if n > MAX_NONCONVEX_CORNERS {
        return Err(FaceError::TooManyCorners { corners: n });
    }
    if crosses_itself(&p) {
        return Err(FaceError::CrossesItself);
    }
    ear_clip(&p, corners, out)
}

/// `(b − a) × (c − a)`: positive when `a, b, c` turn left.
fn cross(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Whether the counter-clockwise polygon `p` is convex: no right turn, and it winds once.
fn is_convex(p: &[DVec2]) -> bool {
    let n = p.len();
    let mut turning = 0.0;
    for i in 0..n {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        if cross(a, b, c) < 0.0 {
            return false;
        }
        let (e, f) = (b - a, c - b);
        turning += e.perp_dot(f).atan2(e.dot(f));
    }
    (turning - std::f64::consts::TAU).abs() < 0.5
}

/// Whether two edges of `p` that share no corner cross or touch.
fn crosses_itself(p: &[DVec2]) -> bool {
    let n = p.len();
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            if segments_meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]) {
                return true;
            }
        }
    }
    false
}

/// Whether segments `ab` and `cd` share a point.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (d1, d2) = (cross(a, b, c), cross(a, b, d));
    let (d3, d4) = (cross(c, d, a), cross(c, d, b));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return true;
    }
    let on = |p: DVec2, q: DVec2, r: DVec2, d: f64| d == 0.0 && r.cmpge(p.min(q)).all() && r.cmple(p.max(q)).all();
    on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4)
}

/// Ear clipping of the simple counter-clockwise polygon `p` (corners `corners`).
fn ear_clip(p: &[DVec2], corners: &[u32], out: &mut Vec<[u32; 3]>) -> Result<(), FaceError> {
    let mut left: Vec<usize> = (0..p.len()).collect();
    let mut i = 0;
    let mut misses = 0;
    while left.len() > 3 {
        let m = left.len();
        let (ia, ib, ic) = (left[(i + m - 1) % m], left[i % m], left[(i + 1) % m]);
        let turn = cross(p[ia], p[ib], p[ic]);
        let is_ear = turn > 0.0
            && left.iter().all(|&k| k == ia || k == ib || k == ic || !in_triangle(p[k], p[ia], p[ib], p[ic]));
        if is_ear || (turn == 0.0 && misses >= m) {
            // An ear, or (once no ear is left) a corner on a straight edge: cut it off.
            if is_ear {
                out.push([corners[ia], corners[ib], corners[ic]]);
            }
            left.remove(i % m);
            i %= m.max(1);
            misses = 0;
        } else {
            i = (i + 1) % m;
            misses += 1;
            if misses > 2 * m {
                return Err(FaceError::Overlaps);
            }
        }
    }
    let (a, b, c) = (left[0], left[1], left[2]);
    if cross(p[a], p[b], p[c]) != 0.0 {
        out.push([corners[a], corners[b], corners[c]]);
    }
    Ok(())
}

/// Whether `q` lies in the counter-clockwise triangle `abc` or on its boundary.
fn in_triangle(q: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(positions: &[Vec3], tris: &[[u32; 3]]) -> f32 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                0.5 * (b - a).cross(c - a).z
            })
            .sum()
    }

    #[test]
    fn non_convex_polygons_are_covered_exactly() {
        // An L shape of area 3, its reflex corner at index 3; a fan from corner 0 would cover 4.
        let p: Vec<Vec3> =
            [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]].map(|[x, y]| Vec3::new(x, y, 0.0)).to_vec();
        for start in 0..6 {
            let corners: Vec<u32> = (0..6).map(|k| (k + start) % 6).collect();
            let mut tris = Vec::new();
            triangulate(&p, &corners, &mut tris).unwrap();
            assert_eq!(tris.len(), 4);
            assert!((area(&p, &tris) - 3.0).abs() < 1e-5, "start {start}: {tris:?}");
            assert!(tris.iter().all(|t| area(&p, &[*t]) > 0.0), "winding kept");
        }
    }

    #[test]
    fn bow_ties_and_stars_are_refused() {
        let bow: Vec<Vec3> = [[0., 0.], [1., 1.], [1., 0.], [0., 1.]].map(|[x, y]| Vec3::new(x, y, 0.0)).to_vec();
        assert_eq!(triangulate(&bow, &[0, 1, 2, 3], &mut Vec::new()), Err(FaceError::CrossesItself));
        let star: Vec<Vec3> = (0..5)
            .map(|k| {
                let a = std::f32::consts::TAU * (2 * k) as f32 / 5.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        assert!(triangulate(&star, &[0, 1, 2, 3, 4], &mut Vec::new()).is_err());
    }

    #[test]
    fn collinear_and_degenerate_polygons_do_not_fail() {
        let p: Vec<Vec3> =
            [[0., 0.], [1., 0.], [2., 0.], [2., 1.], [0., 1.]].map(|[x, y]| Vec3::new(x, y, 0.0)).to_vec();
        let mut tris = Vec::new();
        triangulate(&p, &[0, 1, 2, 3, 4], &mut tris).unwrap();
        assert!((area(&p, &tris) - 2.0).abs() < 1e-6);
        let line: Vec<Vec3> = (0..4).map(|k| Vec3::new(k as f32, 0.0, 0.0)).collect();
        triangulate(&line, &[0, 1, 2, 3], &mut Vec::new()).unwrap();
        let nan = vec![Vec3::NAN, Vec3::X, Vec3::Y, Vec3::ONE];
        triangulate(&nan, &[0, 1, 2, 3], &mut Vec::new()).unwrap();
    }
}
