//! The part of a convex piece of a light where no occluder lies, from the occluders' projected
//! silhouette edges (the soft shadow volumes of Laine et al. 2005 and Lehtinen et al. 2006, made
//! exact): the triangles between a point and its light project onto the light plane, and the number
//! of them over a light point `y` (its depth complexity `D(y)`) is the winding number at `y` of the
//! sum of their projected boundaries, each taken with its orientation's sign. Inside a mesh the
//! edges shared by two triangles facing the same way cancel; what is left are silhouette edges
//! (weight ±2), boundary edges (±1) and whatever non-manifold edges sum to. The lit part of the
//! piece is `{y : D(y) = 0}`; its boundary is made of pieces of those edges and of the piece's own
//! sides, which [`zero_winding_boundary`] finds and hands out one directed segment at a time, so
//! that a contour integral (Lambert's edge formula, an area) can be summed over it.
//!
//! Every decision (does a segment cross another, which side of an edge is an anchor on) is an exact
//! orientation predicate on the `f32` corners as given (Shewchuk's adaptive arithmetic, the
//! `robust` crate), so the arrangement found is the exact one of those segments: the same corner
//! projected twice is the same point, and no result depends on rounding or on jitter. A
//! configuration whose answer would depend on a tie (a corner exactly on another segment) is
//! reported as [`WindingError::Degenerate`] for the caller to resolve another way.

use glam::Vec2;

/// Most segments [`zero_winding_boundary`] takes in one piece.
pub const MAX_WINDING_EDGES: usize = 256;

/// A directed segment of the projected cycle: crossing it from its right to its left adds `weight`
/// to the winding number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindingEdge {
    /// Start.
    pub a: Vec2,
    /// End.
    pub b: Vec2,
    /// Change of the winding number from its right side to its left.
    pub weight: i32,
}

/// Why [`zero_winding_boundary`] gave no answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WindingError {
    /// A corner lies exactly on another segment (or its line, where the two overlap), or the anchor
    /// does: the answer would depend on how the tie is broken.
    Degenerate,
    /// More than [`MAX_WINDING_EDGES`] segments meet the piece.
    Capacity,
}

/// Exact orientation of `c` relative to the directed line `a → b`: positive on its left
/// (counter-clockwise), negative on its right, zero exactly on it (Shewchuk's adaptive predicate).
#[must_use]
#[inline]
pub fn orient2d(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    // Shewchuk's first filter, inline: the f32 corners are exact in f64, so the rounded
    // determinant's sign is right whenever it exceeds this bound; otherwise the adaptive stages.
    let (ax, ay, bx, by, cx, cy) =
        (f64::from(a.x), f64::from(a.y), f64::from(b.x), f64::from(b.y), f64::from(c.x), f64::from(c.y));
    let left = (ax - cx) * (by - cy);
    let right = (ay - cy) * (bx - cx);
    let det = left - right;
    let bound = 3.330_669_073_875_471_6e-16 * (left.abs() + right.abs());
    if det > bound || -det > bound {
        return det;
    }
    let p = |x: f64, y: f64| robust::Coord { x, y };
    robust::orient2d(p(ax, ay), p(bx, by), p(cx, cy))
}

/// How segment `g` crosses segment `e`, from exact predicates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Crossing {
    /// They do not meet (or meet only at a shared end).
    None,
    /// They cross at one point inside both; `start_left`: the first segment starts on the second's
    /// left (so, walked from its start, it crosses the second from left to right).
    Proper { start_left: bool },
}

/// Whether segments `e` and `g` cross. Segments that share an end meet only there unless they
/// overlap, which is degenerate; so is a corner exactly on the other segment's line where their
/// boxes overlap.
#[inline]
fn crossing(e: (Vec2, Vec2), g: (Vec2, Vec2)) -> Result<Crossing, WindingError> {
    let ((ea, eb), (ga, gb)) = (e, g);
    if ea.max(eb).cmplt(ga.min(gb)).any() || ga.max(gb).cmplt(ea.min(eb)).any() {
        return Ok(Crossing::None);
    }
    let shared = [ga == ea || ga == eb, gb == ea || gb == eb];
    if shared[0] && shared[1] {
        return Err(WindingError::Degenerate);
    }
    if shared[0] || shared[1] {
        // Sharing one end: they overlap only when the other end of one lies on the other's line.
        let (free_g, free_e) = (if shared[0] { gb } else { ga }, if ga == ea || gb == ea { eb } else { ea });
        if orient2d(ea, eb, free_g) == 0.0 && orient2d(ga, gb, free_e) == 0.0 {
            return Err(WindingError::Degenerate);
        }
        return Ok(Crossing::None);
    }
    let (o1, o2) = (orient2d(ea, eb, ga), orient2d(ea, eb, gb));
    if (o1 > 0.0 && o2 > 0.0) || (o1 < 0.0 && o2 < 0.0) {
        return Ok(Crossing::None);
    }
    let (o3, o4) = (orient2d(ga, gb, ea), orient2d(ga, gb, eb));
    if (o3 > 0.0 && o4 > 0.0) || (o3 < 0.0 && o4 < 0.0) {
        return Ok(Crossing::None);
    }
    if o1 == 0.0 || o2 == 0.0 || o3 == 0.0 || o4 == 0.0 {
        return Err(WindingError::Degenerate);
    }
    Ok(Crossing::Proper { start_left: o3 > 0.0 })
}

/// Parameter along `a → b` of its crossing with the line `c → d` (rounded; the crossing's existence
/// is decided exactly by [`crossing`]).
fn crossing_parameter(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> f32 {
    let (oa, ob) = (orient2d(c, d, a), orient2d(c, d, b));
    (oa / (oa - ob)) as f32
}

/// The winding number at `to`, from the winding number `winding` at `from`: the weights of the
/// segments of `edges` that the path `from → to` crosses, each counted positive when crossed from
/// its right. `edges` needs to hold only the segments that meet the path.
///
/// # Errors
/// [`WindingError::Degenerate`] when `to`, `from` or a corner lies exactly on the path or a segment.
pub fn winding_after(from: Vec2, winding: i32, to: Vec2, edges: &[WindingEdge]) -> Result<i32, WindingError> {
    crossed(from, winding, (to, 0.0), edges.iter().copied())
}

/// [`winding_after`] over the segments `edges`, where `to = (point, clearance)`: a segment that
/// passes within `clearance` of the point is reported as [`WindingError::Degenerate`]. The point
/// stands for the segment being walked, which it is rounded off by up to an ulp or so; a segment
/// of the cycle that close (a T-junction's edges, a nearly coincident copy) might lie on either
/// side of it, and which side would decide the winding number.
fn crossed(
    from: Vec2,
    winding: i32,
    (to, clearance): (Vec2, f32),
    edges: impl Iterator<Item = WindingEdge>,
) -> Result<i32, WindingError> {
    let mut w = winding;
    for g in edges {
        if let Crossing::Proper { start_left } = crossing((from, to), (g.a, g.b))? {
            w += if start_left { -g.weight } else { g.weight };
        }
        if clearance > 0.0 && g.a.min(g.b).cmple(to + clearance).all() && g.a.max(g.b).cmpge(to - clearance).all() {
            let d = g.b - g.a;
            let t = ((to - g.a).dot(d) / d.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
            if (g.a + d * t).distance(to) < clearance {
                return Err(WindingError::Degenerate);
            }
        }
    }
    Ok(w)
}

/// Whether `y` lies strictly inside the convex counter-clockwise polygon `piece` (exactly).
///
/// # Errors
/// [`WindingError::Degenerate`] when it lies on a side's line without being outside another.
fn inside(piece: &[Vec2], y: Vec2) -> Result<bool, WindingError> {
    let mut on = false;
    for i in 0..piece.len() {
        let o = orient2d(piece[i], piece[(i + 1) % piece.len()], y);
        if o < 0.0 {
            return Ok(false);
        }
        on |= o == 0.0;
    }
    if on { Err(WindingError::Degenerate) } else { Ok(true) }
}

/// A crossing along a segment being walked: its parameter, the change of the winding number on
/// either side of the walked segment past it, and the change of "inside the piece" (for a segment
/// of the cycle crossing a side of the piece).
#[derive(Clone, Copy, Debug)]
struct Event {
    t: f32,
    winding: i32,
    inside: i32,
}

/// What is known on a walked segment's sub-segment: the winding numbers on its left and right and
/// whether it lies in the piece.
#[derive(Clone, Copy, Debug)]
struct State {
    left: i32,
    right: i32,
    inside: i32,
}

impl State {
    fn after(self, e: &Event) -> Self {
        Self { left: self.left + e.winding, right: self.right + e.winding, inside: self.inside + e.inside }
    }

    fn before(self, e: &Event) -> Self {
        Self { left: self.left - e.winding, right: self.right - e.winding, inside: self.inside - e.inside }
    }
}

/// The sub-segments of a segment `a → b` cut at its (sorted) crossings `events`: sub-segment `k`
/// spans `[bound(k), bound(k + 1)]`.
struct Walk<'e> {
    a: Vec2,
    b: Vec2,
    events: &'e [Event],
}

impl Walk<'_> {
    fn bound(&self, k: usize) -> f32 {
        match k {
            0 => 0.0,
            k if k > self.events.len() => 1.0,
            k => self.events[k - 1].t,
        }
    }

    fn point(&self, t: f32) -> Vec2 {
        self.a + (self.b - self.a) * t
    }

    /// The states of the sub-segments from `state` in sub-segment `start`, handed to `out` with
    /// each sub-segment's ends.
    fn each(&self, start: usize, state: State, out: &mut impl FnMut(State, Vec2, Vec2)) {
        let n = self.events.len();
        let mut s = state;
        for k in start..=n {
            out(s, self.point(self.bound(k)), self.point(self.bound(k + 1)));
            if k < n {
                s = s.after(&self.events[k]);
            }
        }
        let mut s = state;
        for k in (0..start).rev() {
            s = s.before(&self.events[k]);
            out(s, self.point(self.bound(k)), self.point(self.bound(k + 1)));
        }
    }
}

/// Most sample points a walked segment tries for its winding numbers.
const SAMPLES: usize = 5;

/// A place to take a walked segment's winding numbers: its sub-segment, the parameter, and the
/// inside count there.
type Sample = (usize, f32, i32);

/// Sort `events` and return up to [`SAMPLES`] places to take a walked segment's winding numbers
/// at, best first: sub-segments for which `take(inside count)` holds, the longest first (far from
/// any crossing), each as (sub-segment, parameter, inside count there); `inside0` is the count
/// before the first event.
fn samples(events: &mut [Event], inside0: i32, take: impl Fn(i32) -> bool) -> ([Sample; SAMPLES], usize) {
    events.sort_unstable_by(|x, y| x.t.total_cmp(&y.t));
    let n = events.len();
    // The three longest eligible sub-segments: (length, index, start, inside).
    let mut top = [(-1.0f32, 0usize, 0.0f32, 0i32); 3];
    let mut inside = inside0;
    for k in 0..=n {
        let s = if k == 0 { 0.0 } else { events[k - 1].t };
        let e = if k == n { 1.0 } else { events[k].t };
        if take(inside) && e - s > top[2].0 {
            top[2] = (e - s, k, s, inside);
            top.sort_unstable_by(|x, y| y.0.total_cmp(&x.0));
        }
        if k < n {
            inside += events[k].inside;
        }
    }
    let mut out = [(0, 0.0, 0); SAMPLES];
    let mut len = 0;
    let (l, k, s, i) = top[0];
    for f in [0.5, 0.3, 0.7] {
        if l >= 0.0 {
            out[len] = (k, s + f * l, i);
            len += 1;
        }
    }
    for &(l, k, s, i) in &top[1..] {
        if l >= 0.0 {
            out[len] = (k, s + 0.5 * l, i);
            len += 1;
        }
    }
    (out, len)
}

/// The first of `samples` at which `at` gives the winding number, with it; `None` when no
/// sample point of the segment is free of ties and close segments.
fn first_clear(
    samples: &[Sample],
    mut at: impl FnMut(f32) -> Result<i32, WindingError>,
) -> Result<Option<(Sample, i32)>, WindingError> {
    if samples.is_empty() {
        return Ok(None);
    }
    for &sample in samples {
        match at(sample.1) {
            Ok(w) => return Ok(Some((sample, w))),
            Err(WindingError::Degenerate) => {}
            Err(e) => return Err(e),
        }
    }
    Err(WindingError::Degenerate)
}

/// Hand `emit` the boundary of `{y ∈ piece : w(y) = 0}` as directed segments with that region on
/// their left (so a contour integral over them, such as Lambert's edge sum or the shoelace area,
/// gives the region's), where `w` is the winding number of the weighted segments `edges` fixed by
/// `w(anchor) = winding`.
///
/// `piece` is convex and counter-clockwise; `anchor` lies strictly inside it and on no segment.
/// Segments that miss the piece may be passed: they are skipped. The winding number is taken as
/// the sum of the weights crossed from the anchor, so `edges` needs to hold only the segments that
/// meet the piece, whatever cycle they belong to. The piece's sides are walked like the segments,
/// so whether a segment meets the piece, and where it enters, is decided by the same exact
/// predicates (a piece cut along a segment of the cycle, as pieces split at the same triangles
/// are, has sides that nearly coincide with it).
///
/// # Errors
/// [`WindingError::Degenerate`] on an exact tie, [`WindingError::Capacity`] past
/// [`MAX_WINDING_EDGES`] segments meeting the piece.
pub fn zero_winding_boundary(
    piece: &[Vec2],
    edges: &[WindingEdge],
    anchor: Vec2,
    winding: i32,
    emit: &mut impl FnMut(Vec2, Vec2),
) -> Result<(), WindingError> {
    Arrangement::new().zero_winding_boundary(piece, edges, anchor, winding, emit)
}

/// The buffers of [`zero_winding_boundary`] (about 10 kB), made once and reused, so that a pass
/// does not fill them anew.
#[derive(Clone, Debug)]
pub struct Arrangement {
    kept: [(WindingEdge, bool); MAX_WINDING_EDGES],
    events: [Event; MAX_WINDING_EDGES + 8],
}

impl Default for Arrangement {
    fn default() -> Self {
        Self::new()
    }
}

impl Arrangement {
    /// Empty buffers.
    #[must_use]
    pub fn new() -> Self {
        Self {
            kept: [(WindingEdge { a: Vec2::ZERO, b: Vec2::ZERO, weight: 0 }, false); MAX_WINDING_EDGES],
            events: [Event { t: 0.0, winding: 0, inside: 0 }; MAX_WINDING_EDGES + 8],
        }
    }

    /// [`zero_winding_boundary`] in these buffers.
    ///
    /// # Errors
    /// As [`zero_winding_boundary`].
    pub fn zero_winding_boundary(
        &mut self,
        piece: &[Vec2],
        edges: &[WindingEdge],
        anchor: Vec2,
        winding: i32,
        emit: &mut impl FnMut(Vec2, Vec2),
    ) -> Result<(), WindingError> {
        let Self { kept, events } = self;
        if !inside(piece, anchor)? {
            return Err(WindingError::Degenerate);
        }
        let side = |i: usize| (piece[i], piece[(i + 1) % piece.len()]);
        let (lo, hi) = piece.iter().fold((piece[0], piece[0]), |(lo, hi), &c| (lo.min(c), hi.max(c)));
        // The segments that meet the piece (a corner inside or a side crossed), with whether their
        // start is inside.
        let mut k = 0;
        for e in edges.iter().filter(|e| e.weight != 0) {
            if e.a.max(e.b).cmplt(lo).any() || e.a.min(e.b).cmpgt(hi).any() {
                continue;
            }
            let start_in = inside(piece, e.a)?;
            let mut meets = start_in || inside(piece, e.b)?;
            for i in 0..piece.len() {
                meets = meets || matches!(crossing((e.a, e.b), side(i))?, Crossing::Proper { .. });
            }
            if meets {
                if k == MAX_WINDING_EDGES {
                    return Err(WindingError::Capacity);
                }
                kept[k] = (*e, start_in);
                k += 1;
            }
        }
        let kept = &kept[..k];
        let cycle =
            |skip: Option<usize>| kept.iter().enumerate().filter(move |&(j, _)| Some(j) != skip).map(|(_, e)| e.0);
        // Clearance of a walked segment's sample point from the other segments: far above the
        // rounding of a point on a segment, far below the size of the light.
        let clearance = 1e-5 * (hi - lo).max_element();
        let winding_at = |m: Vec2, skip: Option<usize>| crossed(anchor, winding, (m, clearance), cycle(skip));
        // Each kept segment: its parts in the piece with w = 0 on exactly one side.
        for (i, &(e, start_in)) in kept.iter().enumerate() {
            let mut n = 0;
            for g in cycle(Some(i)) {
                if let Crossing::Proper { start_left } = crossing((e.a, e.b), (g.a, g.b))? {
                    let t = crossing_parameter(e.a, e.b, g.a, g.b);
                    events[n] = Event { t, winding: if start_left { -g.weight } else { g.weight }, inside: 0 };
                    n += 1;
                }
            }
            for s in 0..piece.len() {
                let (c, d) = side(s);
                if let Crossing::Proper { start_left } = crossing((e.a, e.b), (c, d))? {
                    // Crossing a side from its left (the inside) leaves the piece.
                    events[n] = Event {
                        t: crossing_parameter(e.a, e.b, c, d),
                        winding: 0,
                        inside: if start_left { -1 } else { 1 },
                    };
                    n += 1;
                }
            }
            let events = &mut events[..n];
            let (places, count) = samples(events, i32::from(start_in), |c| c > 0);
            let walk = Walk { a: e.a, b: e.b, events };
            let o = orient2d(e.a, e.b, anchor);
            if o == 0.0 {
                return Err(WindingError::Degenerate);
            }
            let Some(((start, _, inside_count), near)) =
                first_clear(&places[..count], |t| winding_at(walk.point(t), Some(i)))?
            else {
                continue;
            };
            let (left, right) = if o > 0.0 { (near, near - e.weight) } else { (near + e.weight, near) };
            walk.each(start, State { left, right, inside: inside_count }, &mut |s, p, q| {
                if s.inside > 0 && (s.left == 0) != (s.right == 0) && p != q {
                    if s.left == 0 { emit(p, q) } else { emit(q, p) }
                }
            });
        }
        // The piece's sides, where the inside (their left) has w = 0.
        for s in 0..piece.len() {
            let (c, d) = side(s);
            let mut n = 0;
            for g in cycle(None) {
                if let Crossing::Proper { start_left } = crossing((c, d), (g.a, g.b))? {
                    let t = crossing_parameter(c, d, g.a, g.b);
                    events[n] = Event { t, winding: if start_left { -g.weight } else { g.weight }, inside: 0 };
                    n += 1;
                }
            }
            let events = &mut events[..n];
            let (places, count) = samples(events, 0, |_| true);
            let walk = Walk { a: c, b: d, events };
            let Some(((start, _, _), w)) = first_clear(&places[..count], |t| winding_at(walk.point(t), None))? else {
                continue;
            };
            walk.each(start, State { left: w, right: 0, inside: 1 }, &mut |s, p, q| {
                if s.left == 0 && p != q {
                    emit(p, q);
                }
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The winding number of `edges` at `y` by a horizontal half-line to +x (Sunday's crossing
    /// rule), for the brute-force check.
    fn winding_at(edges: &[WindingEdge], y: Vec2) -> i32 {
        let mut w = 0;
        for e in edges {
            let (a, b) = (e.a, e.b);
            if a.y <= y.y && b.y > y.y && orient2d(a, b, y) > 0.0 {
                w += e.weight;
            } else if a.y > y.y && b.y <= y.y && orient2d(a, b, y) < 0.0 {
                w -= e.weight;
            }
        }
        w
    }

    fn rng(seed: u32) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    /// The signed boundary of random triangles' union (their cycles added), against a grid of
    /// samples of the piece: the area the boundary encloses equals the fraction of samples with
    /// zero winding.
    #[test]
    fn boundary_encloses_the_zero_winding_part_of_the_piece() {
        let mut r = rng(5);
        let piece = [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
        for case in 0..200 {
            let mut edges = Vec::new();
            let tris = 1 + case % 7;
            for _ in 0..tris {
                let v: [Vec2; 3] = core::array::from_fn(|_| Vec2::new(1.6 * r() - 0.3, 1.6 * r() - 0.3));
                // A triangle's boundary with its orientation's sign: winding +1 inside either way.
                let s = if orient2d(v[0], v[1], v[2]) > 0.0 { 1 } else { -1 };
                for i in 0..3 {
                    edges.push(WindingEdge { a: v[i], b: v[(i + 1) % 3], weight: s });
                }
            }
            let anchor = Vec2::new(0.5 + 0.1 * (r() - 0.5), 0.5 + 0.1 * (r() - 0.5));
            let w = winding_at(&edges, anchor);
            let mut area = 0.0f64;
            zero_winding_boundary(&piece, &edges, anchor, w, &mut |a, b| {
                area += 0.5 * f64::from(a.perp_dot(b));
            })
            .unwrap();
            let n = 200;
            let mut zero = 0;
            for i in 0..n {
                for j in 0..n {
                    let y = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    zero += usize::from(winding_at(&edges, y) == 0);
                }
            }
            let expected = zero as f64 / (n * n) as f64;
            assert!((area - expected).abs() < 0.01, "case {case}: {area} vs {expected}");
        }
    }

    /// Pieces cut along a segment of the cycle, the cut rounded off the segment's line by 1e-7 or
    /// moved off it by 1e-3: a boundary is either right or refused as degenerate, never wrong.
    #[test]
    fn pieces_cut_along_the_cycle_get_the_sampled_area() {
        let mut r = rng(11);
        let mut degenerate = 0;
        for case in 0..300 {
            let v: [Vec2; 3] = core::array::from_fn(|_| Vec2::new(1.4 * r() - 0.2, 1.4 * r() - 0.2));
            let s = if orient2d(v[0], v[1], v[2]) > 0.0 { 1 } else { -1 };
            let mut edges: Vec<WindingEdge> =
                (0..3).map(|i| WindingEdge { a: v[i], b: v[(i + 1) % 3], weight: s }).collect();
            let w: [Vec2; 3] = core::array::from_fn(|_| Vec2::new(1.4 * r() - 0.2, 1.4 * r() - 0.2));
            let s2 = if orient2d(w[0], w[1], w[2]) > 0.0 { 1 } else { -1 };
            edges.extend((0..3).map(|i| WindingEdge { a: w[i], b: w[(i + 1) % 3], weight: s2 }));
            // The piece: the unit square cut by the line of the first edge (the part on its right),
            // the cut's ends rounded as a split would round them.
            let (a, b) = (v[0], v[1]);
            let square = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
            let mut piece = Vec::new();
            for i in 0..4 {
                let (p, q) = (square[i], square[(i + 1) % 4]);
                let (dp, dq) = ((b - a).perp_dot(p - a), (b - a).perp_dot(q - a));
                if dp <= 0.0 {
                    piece.push(p);
                }
                if (dp < 0.0) != (dq < 0.0) {
                    let t = dp / (dp - dq);
                    let off = if case % 2 == 0 { 1e-7 } else { 1e-3 };
                    piece.push(p + (q - p) * t + Vec2::new(off * (r() - 0.5), off * (r() - 0.5)));
                }
            }
            if piece.len() < 3 {
                continue;
            }
            let area_of = |poly: &[Vec2]| {
                0.5 * (0..poly.len()).map(|i| poly[i].perp_dot(poly[(i + 1) % poly.len()])).sum::<f32>()
            };
            if area_of(&piece) < 0.05 {
                continue;
            }
            let c = piece.iter().copied().sum::<Vec2>() / piece.len() as f32;
            let mut area = 0.0f64;
            match zero_winding_boundary(&piece, &edges, c, winding_at(&edges, c), &mut |a, b| {
                area += 0.5 * f64::from(a.perp_dot(b));
            }) {
                Ok(()) => {}
                Err(WindingError::Degenerate) => {
                    degenerate += case % 2;
                    continue;
                }
                Err(e) => panic!("{e:?}"),
            }
            let n = 300;
            let (mut zero, mut cells) = (0, 0);
            for i in 0..n {
                for j in 0..n {
                    let y = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    if (0..piece.len()).all(|k| (piece[(k + 1) % piece.len()] - piece[k]).perp_dot(y - piece[k]) > 0.0)
                    {
                        cells += 1;
                        zero += usize::from(winding_at(&edges, y) == 0);
                    }
                }
            }
            let expected = zero as f64 / (n * n) as f64;
            assert!(cells > 0);
            if (area - expected).abs() >= 0.006 {
                extern crate std;
                std::eprintln!("piece {piece:?}\nedges {edges:?}\nanchor {c:?} w {}", winding_at(&edges, c));
                zero_winding_boundary(&piece, &edges, c, winding_at(&edges, c), &mut |a, b| {
                    std::eprintln!("emit {a:?} {b:?}")
                })
                .unwrap();
            }
            assert!((area - expected).abs() < 0.006, "case {case}: {area} vs {expected}");
        }
        // Cut within 1e-7 of a segment, the piece's side may be given up on (and the caller splits
        // instead); cut 1e-3 off, rarely.
        assert!(degenerate < 8, "{degenerate}");
    }

    #[test]
    fn shared_corners_are_not_crossings_and_ties_are_reported() {
        let (a, b, c) = (Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0));
        assert_eq!(crossing((a, b), (b, c)), Ok(Crossing::None));
        // Collinear and overlapping from a shared end.
        assert_eq!(crossing((a, b), (a, Vec2::new(0.5, 0.0))), Err(WindingError::Degenerate));
        // A corner exactly on the other segment.
        assert_eq!(crossing((a, b), (Vec2::new(0.5, 0.0), c)), Err(WindingError::Degenerate));
        assert!(matches!(crossing((a, Vec2::ONE), (b, c)), Ok(Crossing::Proper { .. })));
    }

    #[test]
    fn a_covering_loop_leaves_nothing_and_none_leaves_the_piece() {
        let piece = [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
        let mut area = 0.0;
        zero_winding_boundary(&piece, &[], Vec2::splat(0.5), 0, &mut |a, b| area += 0.5 * a.perp_dot(b)).unwrap();
        assert!((area - 1.0).abs() < 1e-6);
        let mut area = 0.0;
        zero_winding_boundary(&piece, &[], Vec2::splat(0.5), 2, &mut |a, b| area += 0.5 * a.perp_dot(b)).unwrap();
        assert_eq!(area, 0.0);
    }
}
