//! A binary tree with spatial splits (Stich, Friedrich, Dietrich, "Spatial Splits in Bounding
//! Volume Hierarchies", 2009), for the 8-wide builder's static-scene modes: besides the binned
//! object split, a node whose children's boxes overlap (more than [`MIN_OVERLAP`] of the root's
//! area) also tries a split plane across its box, binned as in §4.2: a reference goes to every bin
//! its triangle crosses, each time with the box of the triangle's part in that bin (clipped,
//! within the reference's own box), and the counts of references entering and leaving each bin
//! give both sides' sizes. The cheaper split wins. A reference that the plane cuts goes to both
//! sides, unless putting it whole on one side costs less (reference unsplitting, §4.3).
//!
//! The extra references are bounded: a node may add at most its budget, which its children share
//! in proportion to their sizes ([`BuildOptions::spatial`](crate::BuildOptions::spatial) of the
//! input in all). The tree's leaves name ranges of the returned references; a triangle may lie in
//! several leaves, whole (queries test the whole triangle wherever they meet it).

use super::polygon::Polygon;
use crate::binning::{self, Bins, Box4, Context, Measure, PrimRef, Record};
use crate::build::{MAX_SPLIT_DEPTH, Shape, join};
use crate::options::BuildOptions;
use crate::tree::Node;
use beam_math::glam::Vec4;
use beam_math::heuristics::surface_area;
use beam_math::{Aabb, Triangle};
use std::vec::Vec;

/// Spatial splits are tried where the object split's children overlap by more than this fraction
/// of the root's surface area (the paper's α). The paper's 10^-5 gives Sponza the same tree
/// quality (box and triangle tests per ray within 1%) in 1.6 times the build time.
const MIN_OVERLAP: f32 = 3e-3;
/// Bins of a spatial split along each axis (8 or 32 make Sponza's primary rays test 3–9% more
/// boxes).
const SPATIAL_BINS: usize = 16;
/// Nodes of at most this many references take object splits only, by the in-place binary builder
/// (at 16 Sponza's tree builds in 1.25 times as long, with the same work per ray).
const SMALL: usize = 64;
/// Nodes of more references than this build their children in parallel.
const PARALLEL_THRESHOLD: usize = 4096;

/// The tree over `refs` (summarised by `record`) with leaves of at most `options.max_leaf`
/// references, spatial splits adding at most `options.spatial · refs.len()` references; returns
/// the nodes (root first, children after their parents) and the references in leaf order.
pub(super) fn build(
    triangles: &[Triangle],
    refs: Vec<PrimRef>,
    record: Record,
    options: &BuildOptions,
) -> (Vec<Node>, Vec<PrimRef>) {
    let mut out = Tree { nodes: Vec::new(), refs: Vec::new() };
    if refs.is_empty() {
        return out.into_parts();
    }
    let ctx = Context::new(options, 0, Shape::WIDE.grid);
    let root_area = surface_area(record.bounds.aabb());
    let job = Job { ctx: &ctx, triangles, min_overlap: MIN_OVERLAP * root_area };
    let budget = (options.spatial.max(0.0) * refs.len() as f32) as usize;
    job.node(refs, record, 0, budget, &mut out, &mut Box::new(Bins::EMPTY));
    out.into_parts()
}

/// Nodes and references being built.
struct Tree {
    nodes: Vec<Node>,
    refs: Vec<PrimRef>,
}

impl Tree {
    fn into_parts(self) -> (Vec<Node>, Vec<PrimRef>) {
        (self.nodes, self.refs)
    }

    /// Append a subtree built on its own; returns its root's new index.
    fn append(&mut self, sub: Tree) -> u32 {
        let (base, first) = (self.nodes.len() as u32, self.refs.len() as u32);
        self.nodes.extend(sub.nodes.into_iter().map(|n| match n {
            Node::Inner { bounds, left, right } => Node::Inner { bounds, left: left + base, right: right + base },
            Node::Leaf { bounds, first: f, count } => Node::Leaf { bounds, first: f + first, count },
        }));
        self.refs.extend(sub.refs);
        base
    }
}

/// What every node of one build shares.
#[derive(Clone, Copy)]
struct Job<'a> {
    ctx: &'a Context,
    triangles: &'a [Triangle],
    /// [`MIN_OVERLAP`] times the root's area.
    min_overlap: f32,
}

/// A spatial split: references left of plane `bin` (of the node's box along `axis`, in
/// [`SPATIAL_BINS`] equal bins) go left, right of it right, the rest to both sides or one.
#[derive(Clone, Copy, Debug)]
struct SpatialSplit {
    axis: usize,
    lo: f32,
    width: f32,
    bin: usize,
    cost: f32,
    left: usize,
    right: usize,
}

/// The bins of a spatial split search along one axis.
#[derive(Clone, Copy)]
struct Slabs {
    boxes: [Box4; SPATIAL_BINS],
    enter: [u32; SPATIAL_BINS],
    exit: [u32; SPATIAL_BINS],
}

impl Slabs {
    const EMPTY: Self = Self { boxes: [Box4::EMPTY; SPATIAL_BINS], enter: [0; SPATIAL_BINS], exit: [0; SPATIAL_BINS] };

    fn merge(mut self, o: Self) -> Self {
        for b in 0..SPATIAL_BINS {
            self.boxes[b] = self.boxes[b].union(o.boxes[b]);
            self.enter[b] += o.enter[b];
            self.exit[b] += o.exit[b];
        }
        self
    }
}

impl SpatialSplit {
    fn plane(&self) -> f32 {
        self.lo + self.width * self.bin as f32
    }

    /// The bin of coordinate `x`.
    fn bin_of(&self, x: f32) -> usize {
        (((x - self.lo) / self.width) as usize).min(SPATIAL_BINS - 1)
    }
}

impl Job<'_> {
    /// Build the subtree over `refs` into `out`; returns its root's index.
    fn node(
        self,
        mut refs: Vec<PrimRef>,
        record: Record,
        depth: usize,
        budget: usize,
        out: &mut Tree,
        scratch: &mut Bins,
    ) -> u32 {
        let ctx = self.ctx;
        let n = refs.len();
        if budget == 0 || n <= SMALL {
            // No spatial split left to make, or a small node: the in-place binned builder.
            let nodes = crate::build::build_nodes(self.triangles, &mut refs, &record, &ctx.options, Shape::WIDE);
            return out.append(Tree { nodes, refs });
        }
        // Larger than any leaf (`build` gets binary options: leaves of at most four references).
        debug_assert!(n > ctx.options.max_leaf);
        let bounds = record.bounds.aabb();
        let index = out.nodes.len() as u32;
        let object = (depth < MAX_SPLIT_DEPTH)
            .then(|| binning::find_split(ctx, &refs, &record, ctx.measure(bounds), scratch))
            .flatten();
        let (left, right, left_record, right_record) = match object {
            Some(s) => {
                let (mid, l, r) = binning::partition(&mut refs, &s);
                let (lb, rb) = (l.bounds.aabb(), r.bounds.aabb());
                let overlap = Aabb::new(lb.min.max(rb.min), lb.max.min(rb.max));
                let spatial = (overlap.is_valid() && surface_area(overlap) > self.min_overlap)
                    .then(|| self.find_spatial(&refs, bounds))
                    .flatten()
                    .filter(|sp| sp.cost < s.cost && sp.left + sp.right - n <= budget);
                match spatial {
                    Some(sp) => self.spatial_partition(refs, &sp),
                    None => {
                        let right = refs.split_off(mid);
                        (refs, right, l, r)
                    }
                }
            }
            None => {
                let (mid, l, r) = binning::median_split(&mut refs, &record);
                let right = refs.split_off(mid);
                (refs, right, l, r)
            }
        };
        let extra = (left.len() + right.len()).saturating_sub(n);
        let rest = budget.saturating_sub(extra);
        let left_budget = rest * left.len() / (left.len() + right.len()).max(1);
        let right_budget = rest - left_budget;
        out.nodes.push(Node::Leaf { bounds, first: 0, count: 0 });
        let (l, r);
        if ctx.options.parallel && n > PARALLEL_THRESHOLD {
            let (a, b) = join(
                || {
                    let mut t = Tree { nodes: Vec::new(), refs: Vec::new() };
                    self.node(left, left_record, depth + 1, left_budget, &mut t, &mut Box::new(Bins::EMPTY));
                    t
                },
                || {
                    let mut t = Tree { nodes: Vec::new(), refs: Vec::new() };
                    self.node(right, right_record, depth + 1, right_budget, &mut t, &mut Box::new(Bins::EMPTY));
                    t
                },
            );
            l = out.append(a);
            r = out.append(b);
        } else {
            l = self.node(left, left_record, depth + 1, left_budget, out, scratch);
            r = self.node(right, right_record, depth + 1, right_budget, out, scratch);
        }
        out.nodes[index as usize] = Node::Inner { bounds, left: l, right: r };
        index
    }

    /// The cheapest spatial split of `refs` inside `bounds` (§4.2), if any separates them.
    fn find_spatial(&self, refs: &[PrimRef], bounds: Aabb) -> Option<SpatialSplit> {
        let mut best: Option<SpatialSplit> = None;
        for axis in 0..3 {
            let (lo, hi) = (bounds.min[axis], bounds.max[axis]);
            let width = (hi - lo) / SPATIAL_BINS as f32;
            if !(width > 0.0) || lo + width == lo {
                continue;
            }
            let probe = SpatialSplit { axis, lo, width, bin: 0, cost: 0.0, left: 0, right: 0 };
            let bin = |chunk: &[PrimRef]| self.bin(chunk, &probe);
            let Slabs { boxes, enter, exit } =
                binning::reduce_chunks(refs, self.ctx.options.parallel, Slabs::EMPTY, bin, Slabs::merge);
            let mut right_area = [0.0f32; SPATIAL_BINS];
            let mut acc = Box4::EMPTY;
            for b in (1..SPATIAL_BINS).rev() {
                acc = acc.union(boxes[b]);
                right_area[b] = Measure::Surface.area4(acc);
            }
            let (mut acc, mut n_left) = (Box4::EMPTY, 0usize);
            let mut n_right: usize = exit.iter().map(|&c| c as usize).sum();
            for b in 1..SPATIAL_BINS {
                acc = acc.union(boxes[b - 1]);
                n_left += enter[b - 1] as usize;
                n_right -= exit[b - 1] as usize;
                if n_left == 0 || n_right == 0 || n_left == refs.len() || n_right == refs.len() {
                    continue;
                }
                let cost = Measure::Surface.area4(acc) * n_left as f32 + right_area[b] * n_right as f32;
                if best.is_none_or(|s| cost < s.cost) {
                    best = Some(SpatialSplit { bin: b, cost, left: n_left, right: n_right, ..probe });
                }
            }
        }
        best
    }

    /// The bins of `refs` along `probe`'s axis: each reference enters the bin of its box's low
    /// side and leaves from that of its high side, and adds to every bin between the box of its
    /// triangle's part there.
    fn bin(&self, refs: &[PrimRef], probe: &SpatialSplit) -> Slabs {
        let mut out = Slabs::EMPTY;
        let axis = probe.axis;
        for r in refs {
            let (b0, b1) = (probe.bin_of(r.lo[axis]), probe.bin_of(r.hi[axis]));
            out.enter[b0] += 1;
            out.exit[b1] += 1;
            if b0 == b1 {
                out.boxes[b0] = out.boxes[b0].union(r.bounds());
                continue;
            }
            let mut pieces = [Box4::EMPTY; SPATIAL_BINS];
            slab_boxes(&self.triangles[r.index() as usize], probe, &mut pieces[..=b1 - b0], b0);
            for b in b0..=b1 {
                out.boxes[b] = out.boxes[b].union(clamp(pieces[b - b0], r));
            }
        }
        out
    }

    /// The references of each side of `split`, with their records: a reference the plane cuts goes
    /// to both sides as its two parts, or whole to one side where that costs less (§4.3).
    fn spatial_partition(
        &self,
        refs: Vec<PrimRef>,
        split: &SpatialSplit,
    ) -> (Vec<PrimRef>, Vec<PrimRef>, Record, Record) {
        let (axis, plane) = (split.axis, split.plane());
        let (mut l, mut r) = (Record::EMPTY, Record::EMPTY);
        let (mut left, mut right) = (Vec::with_capacity(split.left), Vec::with_capacity(split.right));
        // References the plane cuts, with their two parts.
        let mut straddling = Vec::new();
        for p in refs {
            let (b0, b1) = (split.bin_of(p.lo[axis]), split.bin_of(p.hi[axis]));
            if b1 < split.bin {
                l.add(&p);
                left.push(p);
            } else if b0 >= split.bin {
                r.add(&p);
                right.push(p);
            } else {
                let (a, b) = Polygon::triangle(&self.triangles[p.index() as usize]).cut(axis, plane);
                let piece = |q: &Polygon| PrimRef::with_box(piece_box(q, &p).aabb(), p.index());
                straddling.push((p, piece(&a), piece(&b)));
            }
        }
        // Sides' boxes and counts with every cut reference split; unsplitting compares against them.
        let (n_l, n_r) = ((left.len() + straddling.len()) as f32, (right.len() + straddling.len()) as f32);
        let (mut bl, mut br) = (l.bounds, r.bounds);
        for (_, a, b) in &straddling {
            bl = bl.union(a.bounds());
            br = br.union(b.bounds());
        }
        let area = |b: Box4| Measure::Surface.area4(b);
        let (al, ar) = (area(bl), area(br));
        let split_cost = al * n_l + ar * n_r;
        for (p, a, b) in straddling {
            let whole_left = area(bl.union(p.bounds())) * n_l + ar * (n_r - 1.0);
            let whole_right = al * (n_l - 1.0) + area(br.union(p.bounds())) * n_r;
            let valid = |q: &PrimRef| q.lo.truncate().cmple(q.hi.truncate()).all();
            if whole_left < split_cost.min(whole_right) || !valid(&b) {
                l.add(&p);
                left.push(p);
            } else if whole_right < split_cost || !valid(&a) {
                r.add(&p);
                right.push(p);
            } else {
                l.add(&a);
                left.push(a);
                r.add(&b);
                right.push(b);
            }
        }
        (left, right, l, r)
    }
}

/// The box of piece `p` of the triangle of reference `r`: its clipped polygon's box, [`widen`]ed
/// and kept inside `r`'s box; empty for an empty piece.
fn piece_box(p: &Polygon, r: &PrimRef) -> Box4 {
    if p.len < 3 {
        return Box4::EMPTY;
    }
    let b = p.bounds();
    clamp(widen(Box4 { lo: b.min.extend(0.0), hi: b.max.extend(0.0) }), r)
}

/// `b` (not empty) widened by 2^-20 of its coordinates' magnitude, so that rounding in the
/// clipping never leaves part of a triangle outside every piece's box.
fn widen(b: Box4) -> Box4 {
    let eps = b.lo.abs().max(b.hi.abs()).truncate().max_element() * (1.0 / (1 << 20) as f32);
    Box4 { lo: b.lo - Vec4::splat(eps), hi: b.hi + Vec4::splat(eps) }
}

/// The boxes of the parts of triangle `t` in bins `first..first + out.len()` of `split`'s axis
/// (what clipping the triangle to each bin's slab leaves): each vertex in its bin, and each
/// point where an edge crosses a bin's plane in the bins on both sides of that plane; each box
/// [`widen`]ed.
fn slab_boxes(t: &Triangle, split: &SpatialSplit, out: &mut [Box4], first: usize) {
    let axis = split.axis;
    let last = first + out.len() - 1;
    let add = |out: &mut [Box4], b: usize, p: Vec4| {
        if (first..=last).contains(&b) {
            let o = &mut out[b - first];
            *o = Box4 { lo: o.lo.min(p), hi: o.hi.max(p) };
        }
    };
    for (i, v) in t.v.iter().enumerate() {
        add(out, split.bin_of(v[axis]), v.extend(0.0));
        let w = t.v[(i + 1) % 3];
        let (a, b) = if v[axis] <= w[axis] { (*v, w) } else { (w, *v) };
        let (ba, bb) = (split.bin_of(a[axis]), split.bin_of(b[axis]));
        for plane in ba + 1..=bb {
            let x = split.lo + split.width * plane as f32;
            let f = ((x - a[axis]) / (b[axis] - a[axis])).clamp(0.0, 1.0);
            let mut p = a + (b - a) * f;
            p[axis] = x;
            let p = p.extend(0.0);
            add(out, plane - 1, p);
            add(out, plane, p);
        }
    }
    for o in out.iter_mut().filter(|o| o.lo.x <= o.hi.x) {
        *o = widen(*o);
    }
}

/// `b` within the box of reference `r` (`w` lanes zero); empty where they do not meet.
fn clamp(b: Box4, r: &PrimRef) -> Box4 {
    let lo = b.lo.max(r.lo).truncate().extend(0.0);
    let hi = b.hi.min(r.hi).truncate().extend(0.0);
    if lo.truncate().cmpgt(hi.truncate()).any() { Box4::EMPTY } else { Box4 { lo, hi } }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::traverse::tests::unit_rng;
    use beam_math::glam::Vec3;

    #[test]
    fn slab_boxes_equal_clipping() {
        let mut unit = unit_rng(7);
        let mut r = || unit() * 10.0;
        for _ in 0..1000 {
            let t = Triangle::new(Vec3::new(r(), r(), r()), Vec3::new(r(), r(), r()), Vec3::new(r(), r(), r()));
            let split = SpatialSplit { axis: 1, lo: 0.0, width: 10.0 / 16.0, bin: 0, cost: 0.0, left: 0, right: 0 };
            let pr = PrimRef::with_box(Aabb::from_points(&t.v), 0);
            let (b0, b1) = (split.bin_of(pr.lo[1]), split.bin_of(pr.hi[1]));
            let mut pieces = [Box4::EMPTY; SPATIAL_BINS];
            slab_boxes(&t, &split, &mut pieces[..=b1 - b0], b0);
            let mut rest = Polygon::triangle(&t);
            for b in b0..=b1 {
                let (left, right) = rest.cut(1, split.lo + split.width * (b + 1) as f32);
                let want = if b == b1 { piece_box(&rest, &pr) } else { piece_box(&left, &pr) };
                rest = right;
                let got = clamp(pieces[b - b0], &pr);
                let d = (got.lo - want.lo).abs().max((got.hi - want.hi).abs()).truncate().max_element();
                assert!(
                    d < 1e-3 || (got.lo.x > got.hi.x && want.lo.x > want.hi.x),
                    "bin {b} of {b0}..{b1}: {got:?} vs {want:?}"
                );
            }
        }
    }
}
