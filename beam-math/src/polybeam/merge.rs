//! Joining two pieces of a beam that see the same thing: two convex cross-sections that share a
//! whole edge and whose union is convex become one. Splits cut a beam along the whole lines of
//! triangle edges, so neighbouring triangles of a mesh leave pieces that see one surface side by
//! side; joined, later triangles meet fewer pieces (fewer hit beams, 001 §5.1).

use super::beam::Section;
use glam::Vec2;

/// The union of the convex, counter-clockwise sections `a` and `b` when they share a whole edge
/// (its corners within `tol` of each other, in opposite order) and the union is convex with at
/// most `max` corners; `None` otherwise. A corner within `tol` of the line through its
/// neighbours is dropped, so joining along a straight cut leaves no trace.
#[must_use]
pub fn merge(a: &Section, b: &Section, tol: f32, max: usize) -> Option<Section> {
    let (va, vb) = (a.vertices(), b.vertices());
    let (n, m) = (va.len(), vb.len());
    if n < 3 || m < 3 {
        return None;
    }
    let near = |p: Vec2, q: Vec2| (p - q).abs().max_element() <= tol;
    // A shared edge within rounding of a point would join the two at a corner, not along an edge.
    let (i, j) = (0..n).find_map(|i| {
        let (p, q) = (va[i], va[(i + 1) % n]);
        if (q - p).abs().max_element() <= 16.0 * tol {
            return None;
        }
        (0..m).find(|&j| near(vb[j], q) && near(vb[(j + 1) % m], p)).map(|j| (i, j))
    })?;
    // The outline: a from the shared edge's end round to its start, then b's other corners.
    let total = n + m - 2;
    let corner = |k: usize| if k < n { va[(i + 1 + k) % n] } else { vb[(j + 2 + k - n) % m] };
    // Only the two corners at the ends of the shared edge can turn the wrong way: each must lie
    // outside (right of) the line through its neighbours, or within `tol` of it (then dropped).
    let turn = |k: usize| {
        let (p, v, q) = (corner((k + total - 1) % total), corner(k), corner((k + 1) % total));
        let e = q - p;
        let h = e.perp_dot(v - p) / e.length();
        if h > tol { None } else { Some(h >= -tol) }
    };
    let (drop_first, drop_last) = (turn(0)?, turn(n - 1)?);
    let mut union = Section::new();
    for k in 0..total {
        if !((k == 0 && drop_first) || (k == n - 1 && drop_last)) {
            union.push(corner(k)).ok()?;
        }
    }
    if union.len() < 3 || union.len() > max {
        return None;
    }
    // The union's area is the sum, up to the slivers of moving corners by `tol`.
    let perimeter = |v: &[Vec2]| (0..v.len()).map(|k| (v[(k + 1) % v.len()] - v[k]).length()).sum::<f32>();
    let sum = a.signed_area() + b.signed_area();
    let slack = (tol * (perimeter(va) + perimeter(vb))).min(1e-3 * sum.abs());
    ((union.signed_area() - sum).abs() <= slack).then_some(union)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(v: &[(f32, f32)]) -> Section {
        Section::from_slice(&v.iter().map(|&(x, y)| Vec2::new(x, y)).collect::<Vec<_>>()).unwrap()
    }

    #[test]
    fn two_halves_of_a_square_join_into_it() {
        let left = s(&[(0.0, 0.0), (0.5, 0.0), (0.5, 1.0), (0.0, 1.0)]);
        let right = s(&[(0.5, 0.0), (1.0, 0.0), (1.0, 1.0), (0.5, 1.0)]);
        let m = merge(&left, &right, 1e-6, 8).unwrap();
        assert_eq!(m.len(), 4, "the straight cut leaves no corner: {:?}", m.vertices());
        assert!((m.area() - 1.0).abs() < 1e-6);
        assert_eq!(merge(&right, &left, 1e-6, 8).map(|m| m.len()), Some(4));
    }

    #[test]
    fn a_triangle_and_its_neighbour_join_when_convex() {
        // Two triangles of a quad, with the shared corners a few ulps apart.
        let a = s(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]);
        let b = s(&[(0.0, 0.0), (1.0 + 1e-7, 1.0), (0.0, 1.0)]);
        let m = merge(&a, &b, 1e-6, 8).unwrap();
        assert_eq!(m.len(), 4);
        assert!((m.area() - 1.0).abs() < 1e-5);
        let c = s(&[(1.0, 0.0), (2.0, 0.0), (2.0, 0.4), (1.0, 1.0)]);
        let d = s(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.5)]);
        let m = merge(&d, &c, 1e-6, 8).expect("convex: the outline turns left at both joints");
        assert_eq!(m.len(), 5, "(1, 0) lies on a straight edge: {:?}", m.vertices());
        let e = s(&[(1.0, 0.0), (2.0, 0.0), (2.0, 2.0), (1.0, 1.0)]);
        assert!(merge(&d, &e, 1e-6, 8).is_none(), "reflex at (1, 1)");
        // Edges that overlap only in part are not a shared edge.
        let f = s(&[(1.0, 0.0), (2.0, 0.0), (2.0, 0.5), (1.0, 0.5)]);
        assert!(merge(&d, &f, 1e-6, 8).is_none());
        // Too many corners.
        assert!(merge(&d, &c, 1e-6, 3).is_none());
    }
}
