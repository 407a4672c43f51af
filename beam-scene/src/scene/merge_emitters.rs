//! Neighbouring coplanar emitters of equal radiance joined into one light (issue 66, item 3): a
//! glTF emissive rectangle arrives as two triangles, a tessellated panel as a grid of them, and
//! each light costs every shade point a beam or its rays. The irradiance integral is additive over
//! the light's area, so the join changes no image: two triangles that form a parallelogram become
//! one quad, and two quads that share a whole edge and together form a parallelogram become one,
//! until no pair joins. Corners are matched bit for bit (shared vertices of one mesh), and the
//! joined shape keeps the input's own corners, so that joins go on across a grid.

use super::light::Light;
use beam_math::glam::Vec3;
use std::collections::HashMap;

/// Relative tolerance of the parallelogram test (`a + c = b + d` up to float rounding of the
/// corners, relative to the shape's size).
const PARALLELOGRAM_TOLERANCE: f32 = 1e-5;

/// `lights` with neighbouring coplanar emitters of equal radiance joined, and how many lights the
/// joins removed.
#[must_use]
pub(super) fn merge_emitters(lights: Vec<Light>) -> (Vec<Light>, usize) {
    let before = lights.len();
    let mut shapes: Vec<Option<Shape>> = lights.iter().map(Shape::of).collect();
    loop {
        // Each directed edge of each area light, by its corners' bits.
        let mut edges: HashMap<([u32; 3], [u32; 3]), usize> = HashMap::new();
        for (i, s) in shapes.iter().enumerate() {
            if let Some(s) = s {
                for k in 0..s.len {
                    edges.insert((bits(s.corners[k]), bits(s.corners[(k + 1) % s.len])), i);
                }
            }
        }
        // The joins that work: (shared edge, i, its edge k, j). A neighbour runs the same edge the
        // other way round (the same facing).
        let mut joins: Vec<(Vec3, usize, usize, usize)> = Vec::new();
        for (i, a) in shapes.iter().enumerate() {
            let Some(a) = a else { continue };
            for k in 0..a.len {
                let (p, q) = (a.corners[k], a.corners[(k + 1) % a.len]);
                let Some(&j) = edges.get(&(bits(q), bits(p))) else { continue };
                if let Some(b) = shapes[j].filter(|b| i < j && b.radiance == a.radiance)
                    && a.join(k, &b).is_some()
                {
                    joins.push((q - p, i, k, j));
                }
            }
        }
        if joins.is_empty() {
            break;
        }
        // Longest shared edges first, those along one direction together: the cells of a grid
        // join row by row into strips, and strips into blocks, instead of into a staircase.
        let key = |e: Vec3| (e.length(), e.abs().to_array());
        joins.sort_by(|x, y| {
            let (kx, ky) = (key(x.0), key(y.0));
            ky.0.total_cmp(&kx.0).then_with(|| {
                ky.1.iter().zip(kx.1).fold(core::cmp::Ordering::Equal, |o, (a, b)| o.then(a.total_cmp(&b)))
            })
        });
        let mut touched = vec![false; shapes.len()];
        for (_, i, k, j) in joins {
            if touched[i] || touched[j] {
                continue;
            }
            if let (Some(a), Some(b)) = (shapes[i], shapes[j])
                && let Some(m) = a.join(k, &b)
            {
                (shapes[i], shapes[j]) = (Some(m), None);
                (touched[i], touched[j]) = (true, true);
            }
        }
    }
    let merged: Vec<Light> = lights
        .into_iter()
        .zip(shapes)
        .filter_map(|(l, s)| match l {
            Light::Point { .. } => Some(l),
            _ => s.map(Shape::light),
        })
        .collect();
    let removed = before - merged.len();
    (merged, removed)
}

fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// An area light as its corners in order (3 or 4).
#[derive(Clone, Copy, Debug)]
struct Shape {
    corners: [Vec3; 4],
    len: usize,
    radiance: Vec3,
}

impl Shape {
    fn of(light: &Light) -> Option<Self> {
        let (polygon, radiance) = match *light {
            Light::Point { .. } => return None,
            Light::Quad { radiance, .. } | Light::Triangle { radiance, .. } => (light.polygon(), radiance),
        };
        let mut corners = [Vec3::ZERO; 4];
        corners[..polygon.len()].copy_from_slice(&polygon);
        Some(Self { corners, len: polygon.len(), radiance })
    }

    /// `self` and `other` joined across `self`'s edge `k` (which `other` runs the other way),
    /// where the union is a parallelogram.
    fn join(&self, k: usize, other: &Self) -> Option<Self> {
        let (p, q) = (self.corners[k], self.corners[(k + 1) % self.len]);
        // Two triangles join across the longest edge of each (a rectangle's diagonal), so that the
        // cells of a grid do not pair into slanted parallelograms.
        let longest =
            |s: &Self| (0..s.len).map(|m| (s.corners[(m + 1) % s.len] - s.corners[m]).length()).fold(0.0, f32::max);
        if self.len == 3 && other.len == 3 && ((q - p).length() < longest(self) || (q - p).length() < longest(other)) {
            return None;
        }
        // `other`'s corners after the shared edge, from q back round to p.
        let start = (0..other.len).find(|&m| other.corners[m] == q)?;
        let rest: Vec<Vec3> = (2..other.len).map(|m| other.corners[(start + m) % other.len]).collect();
        // The union's boundary: self's corners from q round to p, then other's after p (back to
        // q); the corners p and q drop out where they are straight.
        let mut ring: Vec<Vec3> = (1..=self.len).map(|m| self.corners[(k + m) % self.len]).collect();
        ring.extend(rest);
        let n = ring.len();
        let kept: Vec<Vec3> = (0..n)
            .filter(|&m| {
                let (a, b, c) = (ring[(m + n - 1) % n], ring[m], ring[(m + 1) % n]);
                let (e, f) = (b - a, c - b);
                e.cross(f).length() > PARALLELOGRAM_TOLERANCE * e.length() * f.length()
            })
            .map(|m| ring[m])
            .collect();
        let [a, b, c, d] = <[Vec3; 4]>::try_from(kept).ok()?;
        let size = (c - a).length().max((d - b).length());
        let normal = |s: &Self| (s.corners[1] - s.corners[0]).cross(s.corners[2] - s.corners[0]);
        let facing = (b - a).cross(d - a).dot(normal(self)) > 0.0;
        (facing && (a + c - b - d).length() <= PARALLELOGRAM_TOLERANCE * size).then_some(Self {
            corners: [a, b, c, d],
            len: 4,
            radiance: self.radiance,
        })
    }

    fn light(self) -> Light {
        let c = self.corners;
        if self.len == 3 {
            return Light::Triangle { v: [c[0], c[1], c[2]], radiance: self.radiance };
        }
        Light::Quad { corner: c[0], edge_u: c[1] - c[0], edge_v: c[3] - c[0], radiance: self.radiance }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Light;

    fn tri(v: [Vec3; 3]) -> Light {
        Light::Triangle { v, radiance: Vec3::ONE }
    }

    fn total_area(l: &[Light]) -> f32 {
        l.iter().map(Light::area).sum()
    }

    #[test]
    fn two_triangles_of_a_rectangle_become_one_quad_facing_the_same_way() {
        let (a, b, c, d) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 2.0), Vec3::Z * 2.0);
        // Facing -y like a ceiling light: (a, d, c) and (a, c, b).
        let lights = vec![tri([a, d, c]), tri([a, c, b])];
        let normal = lights[0].normal();
        let (m, removed) = merge_emitters(lights.clone());
        assert_eq!((m.len(), removed), (1, 1));
        assert!(matches!(m[0], Light::Quad { .. }), "{m:?}");
        assert!((m[0].normal() - normal).length() < 1e-6);
        assert!((total_area(&m) - total_area(&lights)).abs() < 1e-6);
    }

    #[test]
    fn a_grid_of_quads_becomes_one_and_other_lights_stay() {
        let mut lights = Vec::new();
        for i in 0..4 {
            for j in 0..3 {
                let c = Vec3::new(i as f32, 2.0, j as f32);
                // Two triangles a cell, facing down.
                let (a, b, cc, d) = (c, c + Vec3::X, c + Vec3::new(1.0, 0.0, 1.0), c + Vec3::Z);
                lights.push(tri([a, d, cc]));
                lights.push(tri([a, cc, b]));
            }
        }
        lights.push(Light::Point { position: Vec3::ONE, intensity: Vec3::ONE });
        let (m, removed) = merge_emitters(lights.clone());
        assert_eq!((m.len(), removed), (2, 23), "{m:?}");
        assert!((total_area(&m) - 12.0).abs() < 1e-4);
        assert!(m.iter().any(|l| matches!(l, Light::Point { .. })));
    }

    #[test]
    fn unequal_radiance_an_l_shape_and_opposite_facing_do_not_join() {
        let (a, b, c, d) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z);
        let brighter = Light::Triangle { v: [a, c, b], radiance: Vec3::splat(2.0) };
        assert_eq!(merge_emitters(vec![tri([a, d, c]), brighter]).1, 0);
        // Two triangles sharing an edge but not forming a parallelogram (a kite).
        let kite = tri([a, Vec3::new(3.0, 0.0, -1.0), c]);
        assert_eq!(merge_emitters(vec![tri([a, d, c]), kite]).1, 0);
        // Three unit squares in an L: two join, the third cannot join the 2 × 1 quad.
        let sq = |o: Vec3| Light::Quad { corner: o, edge_u: Vec3::Z, edge_v: Vec3::X, radiance: Vec3::ONE };
        let (m, removed) = merge_emitters(vec![sq(Vec3::ZERO), sq(Vec3::X), sq(Vec3::Z)]);
        assert_eq!((m.len(), removed), (2, 1), "{m:?}");
    }
}
