//! The lit part of a light behind a cluster's candidates given as edges (`render/silhouettes`),
//! integrated exactly: each candidate's part in the point's depth range projects onto the light
//! plane, and the number of them over a light point is the winding number of their projected edges
//! weighted by orientation. Most edges cancel; what is left are silhouette and boundary edges and
//! the cuts of the depth range's planes. The winding number is fixed at an anchor by the crossings
//! of a half-line from it (the cycle of edges is closed: it is the sum of the candidates' clipped
//! outlines), and the boundary of the part of the light with no triangle over it gives the
//! irradiance by Lambert's edge formula and the lit area by the shoelace formula, edge by edge
//! (`beam_math::polybeam::zero_winding_boundary`). The cost follows the edges that do not cancel,
//! not the triangles behind them.

use super::ShadowBeam;
use super::winding_scratch::WindingScratch;
use crate::render::lambert::edge_irradiance_f64;
use crate::render::packet::Projector;
use crate::render::silhouettes::{SilEdge, orientation};
use beam_math::Triangle;
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{Section, WindingEdge, WindingError, orient2d};

/// What the pass found: irradiance per unit radiance at the apex (normal `n`) and the lit area on
/// the light plane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Lit {
    pub(crate) irradiance: f32,
    pub(crate) area: f32,
}

/// A position's bits, −0 and +0 as one: the canonical order of an edge's ends.
fn bits(v: Vec3) -> [u32; 3] {
    (v + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// The point where the edge `a`–`b` (depths `ha`, `hb`) crosses depth `plane`, computed from the
/// edge's ends in their canonical order, so that every triangle with this edge gets the same point.
fn cut(a: Vec3, b: Vec3, ha: f32, hb: f32, plane: f32) -> Vec3 {
    let ((a, ha), (b, hb)) = if bits(a) <= bits(b) { ((a, ha), (b, hb)) } else { ((b, hb), (a, ha)) };
    a + (b - a) * ((plane - ha) / (hb - ha))
}

/// The part of segment `a → b` in the depth range of `p` (its ends cut canonically), or `None`.
fn clip_segment(a: Vec3, b: Vec3, p: &Projector) -> Option<(Vec3, Vec3)> {
    let depth = |x: Vec3| (x - p.apex).dot(p.normal);
    let (ha, hb) = (depth(a), depth(b));
    let (lo, hi) = (ha.min(hb), ha.max(hb));
    if hi < p.near || lo > p.far {
        return None;
    }
    let end = |x: Vec3, hx: f32| {
        if hx < p.near {
            cut(a, b, ha, hb, p.near)
        } else if hx > p.far {
            cut(a, b, ha, hb, p.far)
        } else {
            x
        }
    };
    let (ca, cb) = (end(a, ha), end(b, hb));
    (ca != cb).then_some((ca, cb))
}

/// The cuts of triangle `t` by the depth range's planes: the sides of its part in the range that
/// lie on a plane, directed as its corners turn, handed to `emit`.
fn plane_cuts(t: &Triangle, p: &Projector, emit: &mut impl FnMut(Vec3, Vec3)) {
    let h = t.v.map(|v| (v - p.apex).dot(p.normal));
    let inside = |h: f32| h >= p.near && h <= p.far;
    if h.iter().all(|&h| inside(h)) {
        return;
    }
    // The part's outline: kept corners and edge crossings in turn, each with its edge (3: a kept
    // corner, on two edges).
    let mut ring = [(Vec3::ZERO, 0usize); 9];
    let mut n = 0;
    for k in 0..3 {
        let (i, j) = (k, (k + 1) % 3);
        if inside(h[i]) {
            ring[n] = (t.v[i], 3);
            n += 1;
        }
        let mut cross = [(f32::INFINITY, Vec3::ZERO); 2];
        for (c, plane) in cross.iter_mut().zip([p.near, p.far]) {
            if (h[i] < plane) != (h[j] < plane) {
                *c = ((plane - h[i]) / (h[j] - h[i]), cut(t.v[i], t.v[j], h[i], h[j], plane));
            }
        }
        if cross[1].0 < cross[0].0 {
            cross.swap(0, 1);
        }
        for (s, x) in cross {
            if s.is_finite() {
                ring[n] = (x, k);
                n += 1;
            }
        }
    }
    // A side between two crossings of different edges lies on a plane.
    for i in 0..n {
        let ((a, ea), (b, eb)) = (ring[i], ring[(i + 1) % n]);
        if ea != 3 && eb != 3 && ea != eb && a != b {
            emit(a, b);
        }
    }
}

/// The winding number of `cycle` at `y`, by the crossings of the half-line from `y` along +u
/// (Sunday's rule: an edge counts when it goes up through `y`'s height, start included, end not);
/// `None` when `y` lies on an edge.
fn winding_at(cycle: &[WindingEdge], y: Vec2) -> Option<i32> {
    let mut w = 0;
    for e in cycle {
        let (a, b) = (e.a, e.b);
        let up = a.y <= y.y && b.y > y.y;
        let down = b.y <= y.y && a.y > y.y;
        if !(up || down) || (a.x < y.x && b.x < y.x) {
            continue;
        }
        let o = orient2d(a, b, y);
        if o == 0.0 {
            return None;
        }
        if up && o > 0.0 {
            w += e.weight;
        } else if down && o < 0.0 {
            w -= e.weight;
        }
    }
    // A point exactly on a horizontal edge between its ends is on the boundary too.
    cycle
        .iter()
        .all(|e| !(e.a.y == y.y && e.b.y == y.y && y.x >= e.a.x.min(e.b.x) && y.x <= e.a.x.max(e.b.x)))
        .then_some(w)
}

impl ShadowBeam<'_> {
    /// The lit part of the light `section` (the beam's whole cross-section, on its reference plane)
    /// behind a cluster's candidates, given as their edge records `edges` and the candidates that
    /// reach out of some point's depth range `reaching`, at the apex with unit normal `n`.
    ///
    /// # Errors
    /// [`WindingError::Degenerate`] when the arrangement has an exact tie (the caller splits the
    /// beam by the triangles instead), [`WindingError::Capacity`] past `max_edges` edges over the
    /// light (its budget) or the arrangement's capacity.
    pub(crate) fn lit_by_winding(
        &mut self,
        section: &Section,
        (edges, reaching): (&[SilEdge], &[u32]),
        triangles: &[Triangle],
        n: Vec3,
        max_edges: usize,
        scratch: &mut WindingScratch,
    ) -> Result<Lit, WindingError> {
        let projector = self.projector();
        let p = self.frame.apex;
        let light = section.vertices();
        let (lo, hi) = light.iter().fold((light[0], light[0]), |(lo, hi), &c| (lo.min(c), hi.max(c)));
        let WindingScratch { cycle, over, arrangement } = scratch;
        cycle.clear();
        over.clear();
        let mut push = |a: Vec3, b: Vec3, weight: i32| {
            let (a, b) = (projector.project(a), projector.project(b));
            let e = WindingEdge { a, b, weight };
            cycle.push(e);
            if !(a.max(b).cmplt(lo).any() || a.min(b).cmpgt(hi).any()) {
                over.push(e);
            }
        };
        let mut emit_edge = |(a, b, clip): (Vec3, Vec3, bool), weight: i32| {
            if weight == 0 {
                return;
            }
            match clip {
                false => push(a, b, weight),
                true => {
                    if let Some((a, b)) = clip_segment(a, b, &projector) {
                        push(a, b, weight);
                    }
                }
            }
        };
        // Copies of an edge (non-manifold) are next to each other: their weights add.
        let mut pending: Option<((Vec3, Vec3, bool), i32)> = None;
        for e in edges {
            let w = e.weight(p);
            match &mut pending {
                Some(((a, b, _), sum)) if *a == e.a && *b == e.b => *sum += w,
                _ => {
                    if let Some((edge, w)) = pending.take() {
                        emit_edge(edge, w);
                    }
                    pending = Some(((e.a, e.b, e.clip), w));
                }
            }
        }
        if let Some((edge, w)) = pending {
            emit_edge(edge, w);
        }
        // The reaching candidates' cuts by the depth range's planes.
        for &prim in reaching {
            let t = &triangles[prim as usize];
            let nt = t.scaled_normal();
            let s = orientation(nt, nt.dot(t.v[0]), p);
            if s != 0 {
                plane_cuts(t, &projector, &mut |a, b| push(a, b, s));
            }
        }
        self.stats.silhouette_beams += 1;
        self.stats.silhouette_edges += over.len() as u64;
        if over.len() > max_edges {
            return Err(WindingError::Capacity);
        }
        // The anchor: the light's centroid, or a point between it and a corner.
        let centroid = light.iter().copied().sum::<Vec2>() / light.len() as f32;
        let frame = self.frame;
        let (origin, u, v) = (frame.origin.as_dvec3(), frame.u.as_dvec3(), frame.v.as_dvec3());
        let (p64, n64) = (p.as_dvec3(), n.as_dvec3());
        let point = |c: Vec2| origin + u * f64::from(c.x) + v * f64::from(c.y);
        for k in 0..4 {
            let y = if k == 0 { centroid } else { centroid.lerp(light[k % light.len()], 0.37) };
            let Some(w) = winding_at(cycle, y) else { continue };
            let (mut irradiance, mut area) = (0.0f64, 0.0f64);
            let mut emit = |a: Vec2, b: Vec2| {
                irradiance += edge_irradiance_f64(p64, n64, point(a), point(b));
                area += 0.5 * (f64::from(a.x) * f64::from(b.y) - f64::from(a.y) * f64::from(b.x));
            };
            match arrangement.zero_winding_boundary(light, over, y, w, &mut emit) {
                Err(WindingError::Degenerate) => {}
                other => return other.map(|()| Lit { irradiance: irradiance as f32, area: area as f32 }),
            }
        }
        Err(WindingError::Degenerate)
    }
}
