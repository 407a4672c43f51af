//! Exact beam–triangle split (001 §3.2 and App. A): the triangle is clipped to the beam's depth
//! range, projected onto the reference plane, and the cross-section is split edge by edge into one
//! hit part and up to three miss parts, with fuzzy (epsilon) side tests.

use super::beam::{BeamFrame, PolyBeam, Section};
use crate::collide::{CapacityExceeded, ConvexPolygon};
use crate::shapes::Triangle;
use glam::{Vec2, Vec3};

/// Largest number of corners a returned piece has; larger pieces are cut in two (the "extra split"
/// of 001 Fig. 2h, which keeps 4; we keep up to this many).
pub const KEEP_CORNERS: usize = 8;

/// A short list of cross-sections.
#[derive(Clone, Copy, Debug, Default)]
pub struct Pieces {
    items: [Option<Section>; 12],
    len: usize,
}

impl Pieces {
    /// The pieces.
    pub fn iter(&self) -> impl Iterator<Item = &Section> + '_ {
        self.items[..self.len].iter().flatten()
    }

    /// Number of pieces.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there is none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Total area.
    #[must_use]
    pub fn area(&self) -> f32 {
        self.iter().map(Section::area).sum()
    }

    /// Add a piece (already at most [`KEEP_CORNERS`] corners).
    fn push(&mut self, s: Section) -> Result<(), CapacityExceeded> {
        if self.len == self.items.len() {
            return Err(CapacityExceeded);
        }
        self.items[self.len] = Some(s);
        self.len += 1;
        Ok(())
    }
}

/// Which side of a triangle a piece of a split lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Its rays hit the triangle.
    Hit,
    /// Its rays miss it.
    Miss,
}

/// Hand a piece to `emit`, cutting it in two while it has more than [`KEEP_CORNERS`] corners.
fn emit_kept(part: Part, s: Section, emit: &mut impl FnMut(Part, Section)) -> Result<(), CapacityExceeded> {
    if s.len() < 3 {
        return Ok(());
    }
    if s.len() <= KEEP_CORNERS {
        emit(part, s);
        return Ok(());
    }
    let v = s.vertices();
    let k = v.len() / 2;
    emit_kept(part, Section::from_slice(&v[..=k])?, emit)?;
    let mut rest = Section::from_slice(&v[k..])?;
    rest.push(v[0])?;
    emit_kept(part, rest, emit)
}

/// The outcome of splitting a beam by a triangle.
#[derive(Clone, Copy, Debug, Default)]
pub struct Split {
    /// Parts of the cross-section whose rays hit the triangle (one, or two after an extra split).
    pub hit: Pieces,
    /// Parts whose rays miss it.
    pub miss: Pieces,
}

/// Most corners a triangle keeps after clipping by the near, far and four window planes (9), and
/// by one more line in the image (10).
const CLIPPED: usize = 10;

/// Clip a triangle by half-spaces `n·(x − origin) ≤ d` (Sutherland–Hodgman in 3D). Relative to the
/// apex, so that rounding follows the beam's size, not the scene's coordinates.
fn clip_planes(tri: &Triangle, planes: &[(Vec3, f32)], origin: Vec3) -> ([Vec3; CLIPPED], usize) {
    let mut poly = [Vec3::ZERO; CLIPPED];
    poly[..3].copy_from_slice(&tri.v);
    // Common case: wholly inside every half-space, nothing to clip.
    if planes.iter().all(|&(normal, d)| tri.v.iter().all(|&p| normal.dot(p - origin) <= d)) {
        return (poly, 3);
    }
    let mut n = 3;
    for &(normal, d) in planes {
        let mut out = [Vec3::ZERO; CLIPPED];
        let mut m = 0;
        for i in 0..n {
            let p = poly[i];
            let q = poly[(i + 1) % n];
            let dp = d - normal.dot(p - origin);
            let dq = d - normal.dot(q - origin);
            if dp >= 0.0 && m < CLIPPED {
                out[m] = p;
                m += 1;
            }
            if ((dp < 0.0) != (dq < 0.0)) && m < CLIPPED {
                out[m] = p + (q - p) * (dp / (dp - dq));
                m += 1;
            }
        }
        poly = out;
        n = m;
        if n < 3 {
            return (poly, 0);
        }
    }
    (poly, n)
}

/// The half-spaces (relative to the apex) of a beam between depths `near` and `far` (infinite:
/// none), and, with a window `[lo, hi]` on the reference plane, the four planes through the apex and
/// the window's sides.
fn beam_planes(frame: &BeamFrame, near: f32, far: f32, window: Option<(Vec2, Vec2)>) -> ([(Vec3, f32); 6], usize) {
    let mut planes = [(Vec3::ZERO, 0.0); 6];
    let mut k = 0;
    let n = frame.normal / frame.distance;
    // depth(x) = n·(x − apex): near keeps depth ≥ near, far keeps depth ≤ far.
    planes[k] = (-n, -near);
    k += 1;
    if far.is_finite() {
        planes[k] = (n, far);
        k += 1;
    }
    if let Some((lo, hi)) = window {
        for m in frame.side_normals(lo, hi) {
            planes[k] = (m, 0.0);
            k += 1;
        }
    }
    (planes, k)
}

/// A triangle clipped to a beam's depth range and projected through its apex onto the reference
/// plane (001 §3.2 step 1), ready to split any section of beams sharing the frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectedTriangle {
    /// The projected polygon (3 to 10 corners after clipping).
    pub polygon: ConvexPolygon<CLIPPED>,
    /// Its bounding rectangle, lower corner.
    pub min: Vec2,
    /// Its bounding rectangle, upper corner.
    pub max: Vec2,
}

impl ProjectedTriangle {
    /// Clip `tri` to depths `[near, far]` of `frame` and project it; `None` when nothing remains.
    #[must_use]
    pub fn new(frame: &BeamFrame, tri: &Triangle, near: f32, far: f32) -> Option<Self> {
        let (planes, k) = beam_planes(frame, near, far, None);
        let (poly, n) = clip_planes(tri, &planes[..k], frame.apex);
        Self::project(frame, &poly[..n])
    }

    /// As [`ProjectedTriangle::new`], also clipped in 3D to the beam through the window `[lo, hi]`
    /// of the reference plane, widened by a tenth of its size. Only the triangle's part near the
    /// window can split sections inside it, and clipping first keeps the projected corners near the
    /// window: a triangle reaching close to the apex would otherwise project to coordinates ~1/near
    /// times larger, whose rounding swamps the window's size.
    #[must_use]
    pub fn new_in_window(frame: &BeamFrame, tri: &Triangle, near: f32, far: f32, lo: Vec2, hi: Vec2) -> Option<Self> {
        let margin = 0.1 * (hi - lo);
        let (planes, k) = beam_planes(frame, near, far, Some((lo - margin, hi + margin)));
        let (poly, n) = clip_planes(tri, &planes[..k], frame.apex);
        Self::project(frame, &poly[..n])
    }

    /// The part on the inner side `n·(x − a) ≤ 0` of a line; `None` when nothing (or a sliver of
    /// fewer than three corners) remains. Should the corners outgrow the capacity, the whole
    /// triangle (which contains that part).
    #[must_use]
    pub fn clip(&self, a: Vec2, n: Vec2) -> Option<Self> {
        let Ok(polygon) = self.polygon.clip(a, n) else { return Some(*self) };
        if polygon.len() < 3 {
            return None;
        }
        let (min, max) = polygon.bounds();
        Some(Self { polygon, min, max })
    }

    /// True when the projection's bounding rectangle meets the rectangle `[lo, hi]`.
    #[must_use]
    pub fn overlaps(&self, lo: Vec2, hi: Vec2) -> bool {
        self.max.x >= lo.x && self.max.y >= lo.y && self.min.x <= hi.x && self.min.y <= hi.y
    }

    /// Project a clipped polygon; `None` for fewer than three corners.
    fn project(frame: &BeamFrame, poly: &[Vec3]) -> Option<Self> {
        if poly.len() < 3 {
            return None;
        }
        let mut polygon = ConvexPolygon::<CLIPPED>::new();
        let (mut min, mut max) = (Vec2::INFINITY, Vec2::NEG_INFINITY);
        for p in poly {
            let q = frame.project(*p);
            min = min.min(q);
            max = max.max(q);
            polygon.push(q).ok()?;
        }
        Some(Self { polygon, min, max })
    }
}

impl PolyBeam {
    /// Split this beam by a triangle into hit and miss parts (001 §3.2). Only the part of the
    /// triangle with depth in `[near, far]` (units of the reference-plane distance) counts, so a
    /// shadow beam ends at its light. Side tests treat corners within `eps` (a fraction of the
    /// section's size) of an edge as undecided, the fuzzy logic of 001 App. A.
    ///
    /// Trivial cases first (001 Fig. 2a–c): a triangle edge separating the triangle from the beam,
    /// a beam edge separating the beam from the triangle, or the beam inside the triangle.
    pub fn split(&self, tri: &Triangle, near: f32, far: f32, eps: f32) -> Result<Split, CapacityExceeded> {
        let mut out = Split::default();
        let mut failed = false;
        let mut collect = |part, s| {
            let list = if part == Part::Hit { &mut out.hit } else { &mut out.miss };
            failed |= list.push(s).is_err();
        };
        match ProjectedTriangle::new(&self.frame, tri, near, far) {
            Some(projected) => split_section(&self.section, &projected, eps, &mut collect)?,
            None => collect(Part::Miss, self.section),
        }
        if failed { Err(CapacityExceeded) } else { Ok(out) }
    }
}

/// Split a section by a projected triangle (see [`PolyBeam::split`]), handing each hit and miss
/// piece to `emit` (pieces of more than [`KEEP_CORNERS`] corners cut in two first). A section whose
/// bounding rectangle misses the triangle's is handed on whole as a miss at once. On
/// `CapacityExceeded` the pieces emitted so far are incomplete; callers keep the section whole.
pub fn split_section(
    section: &Section,
    projected: &ProjectedTriangle,
    eps: f32,
    emit: &mut impl FnMut(Part, Section),
) -> Result<(), CapacityExceeded> {
    let proj = &projected.polygon;
    let (lo, hi) = section.bounds();
    if !projected.overlaps(lo, hi) {
        emit(Part::Miss, *section);
        return Ok(());
    }
    let scale = section.vertices().iter().fold(0.0f32, |m, v| m.max((*v - section.centroid()).length()));
    let eps = eps * scale.max(f32::MIN_POSITIVE);
    let area = proj.signed_area();
    // A polygon within a few tolerances of a point hides nothing: its edges would all be skipped
    // below as too short to have a direction, leaving the half-planes of none or some of them,
    // which cover far more than the polygon.
    if area.abs() <= eps * eps || (projected.max - projected.min).max_element() <= 32.0 * eps {
        emit(Part::Miss, *section);
        return Ok(());
    }
    let sign = area.signum();
    let edges = proj.vertices();
    // Outward normal of edge i of the projected polygon. An edge within rounding of zero length
    // (clipping at a corner can repeat it, a few ulps apart) has no meaningful direction: it gets a
    // zero normal and is skipped below, which moves the polygon's outline by less than its length
    // where its neighbours meet beyond it (at the end of a thin sliver, where they meet behind it,
    // the sliver is prolonged by a wedge as thin as itself).
    let edge = |i: usize| {
        let a = edges[i];
        let e = edges[(i + 1) % edges.len()] - a;
        let n = if e.length() <= 16.0 * eps { Vec2::ZERO } else { sign * Vec2::new(e.y, -e.x).normalize() };
        (a, n)
    };
    let beam = section.vertices();
    // Fig. 2a: a triangle edge with every beam corner outside.
    for i in 0..edges.len() {
        let (a, nrm) = edge(i);
        if nrm != Vec2::ZERO && beam.iter().all(|c| nrm.dot(*c - a) >= -eps) {
            emit(Part::Miss, *section);
            return Ok(());
        }
    }
    // Fig. 2b: a beam edge with every triangle corner outside (the section is counter-clockwise).
    // Edges within rounding of zero length are skipped, as above.
    for i in 0..beam.len() {
        let a = beam[i];
        let e = beam[(i + 1) % beam.len()] - a;
        if e.length() <= 16.0 * eps {
            continue;
        }
        let nrm = Vec2::new(e.y, -e.x).normalize();
        if edges.iter().all(|c| nrm.dot(*c - a) >= -eps) {
            emit(Part::Miss, *section);
            return Ok(());
        }
    }
    // Fig. 2d–g: split edge by edge; what lies outside an edge misses.
    let mut rest = *section;
    for i in 0..edges.len() {
        let (a, nrm) = edge(i);
        if nrm == Vec2::ZERO {
            continue;
        }
        let (inside, outside) = rest.split(a, nrm, eps)?;
        if inside.is_empty() {
            return emit_kept(Part::Miss, rest, emit);
        }
        if !outside.is_empty() {
            emit_kept(Part::Miss, outside, emit)?;
        }
        rest = inside;
    }
    emit_kept(Part::Hit, rest, emit)
}
