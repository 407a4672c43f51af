//! Closest distances between points, segments and triangles, used for the threshold-plane
//! condition `min ‖P_res − P_max‖ > μ_b + t_max μ_d` of 000 §5 and §6.2.

use crate::shapes::Triangle;
use glam::Vec3;

/// The point of triangle `tri` closest to `p` (Ericson, *Real-Time Collision Detection* §5.1.5).
#[must_use]
pub fn closest_point_on_triangle(p: Vec3, tri: &Triangle) -> Vec3 {
    let [a, b, c] = tri.v;
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Closest distance between segments `p0p1` and `q0q1` (Ericson §5.1.9).
#[must_use]
pub fn segment_segment_distance(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> f32 {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = d1.dot(d1);
    let e = d2.dot(d2);
    let f = d2.dot(r);
    let (s, t);
    if a <= f32::EPSILON && e <= f32::EPSILON {
        return r.length();
    }
    if a <= f32::EPSILON {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= f32::EPSILON {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let s0 = if denom != 0.0 { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    ((p0 + d1 * s) - (q0 + d2 * t)).length()
}

/// True when segment `p0p1` crosses the (closed) triangle.
fn segment_crosses_triangle(p0: Vec3, p1: Vec3, tri: &Triangle) -> bool {
    let n = tri.scaled_normal();
    let s0 = n.dot(p0 - tri.v[0]);
    let s1 = n.dot(p1 - tri.v[0]);
    if (s0 > 0.0 && s1 > 0.0) || (s0 < 0.0 && s1 < 0.0) || s0 == s1 {
        return false;
    }
    let x = p0 + (p1 - p0) * (s0 / (s0 - s1));
    tri.barycentric(x).is_some_and(|w| w.min_element() >= 0.0)
}

/// Closest distance between two triangles: zero when they intersect, otherwise the least of the six
/// vertex–triangle and nine edge–edge distances.
#[must_use]
pub fn triangle_triangle_distance(a: &Triangle, b: &Triangle) -> f32 {
    for i in 0..3 {
        let (p, q) = (a.v[i], a.v[(i + 1) % 3]);
        let (r, s) = (b.v[i], b.v[(i + 1) % 3]);
        if segment_crosses_triangle(p, q, b) || segment_crosses_triangle(r, s, a) {
            return 0.0;
        }
    }
    let mut best = f32::INFINITY;
    for i in 0..3 {
        best = best.min(a.v[i].distance(closest_point_on_triangle(a.v[i], b)));
        best = best.min(b.v[i].distance(closest_point_on_triangle(b.v[i], a)));
        for j in 0..3 {
            best = best.min(segment_segment_distance(a.v[i], a.v[(i + 1) % 3], b.v[j], b.v[(j + 1) % 3]));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!((closest_point_on_triangle(Vec3::new(0.2, 0.2, 1.0), &t) - Vec3::new(0.2, 0.2, 0.0)).length() < 1e-6);
        assert_eq!(closest_point_on_triangle(Vec3::new(-1.0, -1.0, 0.0), &t), Vec3::ZERO);
        let d = segment_segment_distance(Vec3::ZERO, Vec3::X, Vec3::new(0.5, 1.0, -1.0), Vec3::new(0.5, 1.0, 1.0));
        assert!((d - 1.0).abs() < 1e-6);
        let lifted = Triangle::new(Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 1.0, 2.0));
        assert!((triangle_triangle_distance(&t, &lifted) - 2.0).abs() < 1e-6);
        let crossing = Triangle::new(Vec3::new(0.2, 0.2, -1.0), Vec3::new(0.2, 0.2, 1.0), Vec3::new(3.0, 3.0, 0.0));
        assert_eq!(triangle_triangle_distance(&t, &crossing), 0.0);
    }
}
