//! The occluders of a cluster of shade points as edges (see `shadow_beam/silhouette.rs` for their
//! use): every candidate triangle of the cluster projects onto the light, and the number of them
//! over a light point is the winding number of their projected edges, each weighted by its
//! triangles' orientations. An edge between two triangles that every point of the cluster sees
//! turned the same way (as the triangles inside a mesh, seen from outside it) cancels for all of
//! them and is left out here; what is kept are the edges that are a silhouette for some point of the
//! cluster, boundary and non-manifold edges, and the triangles that some point sees reaching out of
//! its depth range (clipped per point).

use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};
use beam_render::tolerance::DEPTH_EPS;

/// One triangle's part in an edge's weight.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Side {
    /// The triangle's scaled normal (as its corners turn) and `n·v₀`.
    pub(crate) n: Vec3,
    pub(crate) d: f32,
    /// +1 when the triangle runs the edge `a → b`, −1 when `b → a`.
    pub(crate) sigma: i8,
    /// The triangle's orientation seen from every point of the cluster ([`orientation`]), or 0
    /// where the points see it both ways.
    pub(crate) fixed: i8,
}

impl Side {
    fn of(t: &Triangle, sigma: i8, fixed: i8) -> Self {
        let n = t.scaled_normal();
        Self { n, d: n.dot(t.v[0]), sigma, fixed }
    }

    /// The triangle's orientation seen from `p`.
    #[inline]
    pub(crate) fn orientation(&self, p: Vec3) -> i32 {
        match self.fixed {
            0 => orientation(self.n, self.d, p),
            s => i32::from(s),
        }
    }
}

/// An edge that may carry a weight for some point of the cluster: its corners and the one or two
/// triangles that have it. Copies of an edge that more triangles share (non-manifold) come one
/// per triangle, next to each other.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SilEdge {
    pub(crate) a: Vec3,
    pub(crate) b: Vec3,
    pub(crate) sides: [Side; 2],
    pub(crate) count: u8,
    /// One of its triangles reaches out of some point's depth range: the edge is clipped to it.
    pub(crate) clip: bool,
}

impl SilEdge {
    /// The edge's weight seen from `p`: the sum over its triangles of orientation times direction
    /// (crossing the projected edge from its right to its left adds this many triangles over the
    /// light point).
    #[inline]
    pub(crate) fn weight(&self, p: Vec3) -> i32 {
        self.sides[..usize::from(self.count)].iter().map(|s| s.orientation(p) * i32::from(s.sigma)).sum()
    }
}

/// The orientation of a triangle of normal `n` (and `n·v₀ = d`) as projected from `p` onto a light
/// plane in a shadow beam's coordinates: +1 counter-clockwise, −1 clockwise, 0 edge-on. The plane's
/// axes `(u, v)` turn about the normal pointing away from `p`, so a triangle that faces `p` (turns
/// counter-clockwise seen from `p`) projects clockwise.
#[inline]
pub(crate) fn orientation(n: Vec3, d: f32, p: Vec3) -> i32 {
    let s = n.dot(p) - d;
    if s > 0.0 {
        -1
    } else if s < 0.0 {
        1
    } else {
        0
    }
}

/// The orientation of `n·x = d` over the box `b` when every corner sees it the same way by a margin
/// (so every point of the box does), else 0.
fn fixed_orientation(t: &Triangle, b: &Aabb) -> i8 {
    let n = t.scaled_normal();
    let d = n.dot(t.v[0]);
    let scale = n.length() * (b.extent().length() + b.center().abs().max_element() + t.v[0].abs().max_element());
    let margin = 1e-5 * scale;
    let (lo, hi) = b.corners().iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), c| {
        let s = n.dot(*c) - d;
        (lo.min(s), hi.max(s))
    });
    if lo > margin {
        -1
    } else if hi < -margin {
        1
    } else {
        0
    }
}

/// The light as the cluster sees it: its plane.
pub(crate) struct Light {
    pub(crate) normal: Vec3,
    pub(crate) center: Vec3,
}

/// A cluster's edge set in the making.
#[derive(Default)]
pub(crate) struct WindingBuilder {
    /// The candidates with whether they reach out of some point's depth range and their
    /// orientation over the cluster.
    status: Vec<(u32, bool, i8)>,
    /// Every candidate's edges: the ends' bits in canonical order, the candidate (its place in
    /// `status`) and edge, and whether it runs the edge in the canonical direction.
    ends: Vec<([u32; 6], u32, u8, bool)>,
    /// The edges grouped by their ends: a hash table of groups (1 + index, 0 where empty), each
    /// group's first and last place in `ends`, and each place's next in its group.
    table: Vec<u32>,
    groups: Vec<(u32, u32)>,
    next: Vec<u32>,
}

/// A position's bits, −0 and +0 as one: which corners are the same.
fn bits(v: Vec3) -> [u32; 3] {
    (v + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// A hash of an edge's ends' bits: equal edges get equal hashes.
fn edge_hash(key: &[u32; 6]) -> u64 {
    key.iter().fold(0u64, |h, &x| (h ^ u64::from(x)).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29))
}

impl WindingBuilder {
    /// The edges of `candidates` for a cluster of points in `points` and `light`, appended to
    /// `edges`, and the candidates that reach out of some point's depth range, appended to
    /// `reaching` (their cuts by the range's planes are made per point). Candidates are neighbours
    /// where they share an edge's two corners exactly (as an indexed mesh's triangles do); an edge
    /// of a candidate with none or several such neighbours among the candidates comes once per
    /// candidate, its copies next to each other.
    pub(crate) fn build(
        &mut self,
        triangles: &[Triangle],
        points: &Aabb,
        light: &Light,
        candidates: &[u32],
        edges: &mut Vec<SilEdge>,
        reaching: &mut Vec<u32>,
    ) {
        let height = |x: Vec3| light.normal.dot(x - light.center);
        let (h_lo, h_hi) = points.corners().iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), &c| {
            let h = height(c);
            (lo.min(h), hi.max(h))
        });
        // Depth d = 1 − h(x)/h(p): in [2ε, 1 − 2ε] for every point when these hold.
        let margin = 2.0 * DEPTH_EPS;
        self.status.clear();
        self.status.extend(candidates.iter().map(|&prim| {
            let t = &triangles[prim as usize];
            let inside = t.v.iter().all(|&v| {
                let h = height(v);
                h <= (1.0 - margin) * h_lo && h >= margin * h_hi
            });
            (prim, !inside, fixed_orientation(t, points))
        }));
        reaching.extend(self.status.iter().filter(|s| s.1).map(|s| s.0));
        self.ends.clear();
        for (i, &(f, _, _)) in self.status.iter().enumerate() {
            let t = &triangles[f as usize];
            for k in 0..3 {
                let (a, b) = (bits(t.v[k]), bits(t.v[(k + 1) % 3]));
                let forward = a <= b;
                let (lo, hi) = if forward { (a, b) } else { (b, a) };
                let key = [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]];
                self.ends.push((key, i as u32, k as u8, forward));
            }
        }
        // The candidates that share an edge, grouped (in the order the groups first come).
        self.group_ends();
        let side = |&(_, i, k, forward): &([u32; 6], u32, u8, bool), sigma: i8| {
            let (f, f_reaches, fixed) = self.status[i as usize];
            let t = &triangles[f as usize];
            let (a, b) = (t.v[k as usize], t.v[(k as usize + 1) % 3]);
            let (a, b) = if forward { (a, b) } else { (b, a) };
            (a, b, Side::of(t, sigma, fixed), f_reaches)
        };
        for &(first, _) in &self.groups {
            let (e, second) = (&self.ends[first as usize], self.next[first as usize]);
            if second != NONE && self.next[second as usize] == NONE {
                let g = &self.ends[second as usize];
                // Two candidates on this edge: one record in the first's direction, the second's
                // direction relative to it.
                let (a, b, sf, f_reaches) = side(e, 1);
                let (_, _, sg, g_reaches) = side(g, if e.3 == g.3 { 1 } else { -1 });
                let (a, b) = if e.3 { (a, b) } else { (b, a) };
                let clip = f_reaches || g_reaches;
                // Seen turned the same way from every point, a pair inside the depth range
                // cancels for all of them.
                if !clip && sf.fixed != 0 && sg.fixed != 0 && sf.fixed * sf.sigma + sg.fixed * sg.sigma == 0 {
                    continue;
                }
                edges.push(SilEdge { a, b, sides: [sf, sg], count: 2, clip });
            } else {
                // One candidate (a boundary, or a neighbour that is not one), or several: each
                // comes on its own, in the canonical direction, so their weights add per beam.
                let mut at = first;
                while at != NONE {
                    let e = &self.ends[at as usize];
                    let (a, b, s, reaches) = side(e, if e.3 { 1 } else { -1 });
                    edges.push(SilEdge { a, b, sides: [s, s], count: 1, clip: reaches });
                    at = self.next[at as usize];
                }
            }
        }
    }

    /// Group `ends` by their ends' bits, exactly: `groups` in the order they first come, each a
    /// list through `next`.
    fn group_ends(&mut self) {
        let n = self.ends.len();
        let mask = (2 * n).next_power_of_two().max(16) - 1;
        self.table.clear();
        self.table.resize(mask + 1, 0);
        self.groups.clear();
        self.next.clear();
        self.next.resize(n, NONE);
        for (i, e) in self.ends.iter().enumerate() {
            let mut slot = edge_hash(&e.0) as usize & mask;
            loop {
                match self.table[slot] {
                    0 => {
                        self.groups.push((i as u32, i as u32));
                        self.table[slot] = self.groups.len() as u32;
                        break;
                    }
                    g => {
                        let group = &mut self.groups[g as usize - 1];
                        if self.ends[group.0 as usize].0 == e.0 {
                            self.next[group.1 as usize] = i as u32;
                            group.1 = i as u32;
                            break;
                        }
                        slot = (slot + 1) & mask;
                    }
                }
            }
        }
    }
}

/// No next end in a group.
const NONE: u32 = u32::MAX;

/// Fewest splits of a beam whose cluster may be cheaper by edges ([`WindingWork::may_pay`]).
const MIN_SPLITS: u64 = 5;

/// The work of a cluster's winding pass for one beam, to weigh against splitting by its candidates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WindingWork {
    /// Edge records of the cluster.
    pub(crate) records: usize,
    /// Reaching candidates (cut per point).
    pub(crate) reaching: usize,
    /// Projected edges over the light.
    pub(crate) edges_over: u64,
}

impl WindingWork {
    /// Whether the winding pass costs less than splitting by `candidates` triangles with `splits`
    /// piece splits, by the time each step took in a fit over the beams of the bunny and the suite
    /// (nanoseconds on this machine; only their ratios matter).
    pub(crate) fn cheaper_than(&self, candidates: usize, splits: u64) -> bool {
        let k = self.edges_over as f64;
        let winding = 17.0 * self.records as f64 + 300.0 * self.reaching as f64 + 25.0 * k * k + 1000.0 * k;
        let split = 3.5 * candidates as f64 + 211.0 * splits as f64;
        winding < split
    }

    /// Whether a winding pass may cost less than splitting by a cluster's candidates where a beam
    /// of it split `splits` times: a split means an edge over the light, which costs the pass as
    /// much as [`MIN_SPLITS`] splits (1 µs against 211 ns in [`WindingWork::cheaper_than`]).
    /// Building the cluster's edges costs more than a beam's splitting (25 µs a cluster on Sponza
    /// at 256²), so they are built only where this holds.
    pub(crate) fn may_pay(splits: u64) -> bool {
        splits >= MIN_SPLITS
    }
}
