//! A hierarchy of bounding cones over the light beams (002 §5.2 asks for it, after Chuang and
//! Cheng 1995), so that the gather at a point visits only the beams whose cones contain it.
//!
//! Why a beam's cone is conservative: a point `F` of a beam's flux triangle is
//! `F = Σ wᵢ (Oᵢ + tᵢ dᵢ)` with barycentric `wᵢ ≥ 0` and `tᵢ ≥ 0` (in front), that is `F = P + v` with
//! `P = Σ wᵢ Oᵢ` on the scatterer triangle and `v = Σ wᵢ tᵢ dᵢ` in the convex cone of the scattered
//! directions. That cone lies in the circular cone of axis `a` and half-angle
//! `β = maxᵢ ∠(a, dᵢ) < 90°` (circular cones are convex), and the scatterer triangle lies in the
//! ball of radius `R` about its centroid `c`, which the circular cone of half-angle `β` with apex
//! `c − a·R/sin β` contains. A convex cone `K` with its apex moved back contains `K`'s points plus
//! any of its directions, so it holds every `F`. A node's cone holds its children's: its axis and
//! half-angle cover their direction cones and its apex is moved back until their apexes lie in it.
//! For glossy beams the support is cut off at the beam's cone widened by `K·σ`: outside it every
//! vertex of the scatter-angle domain `ABC` lies more than `K·σ` from the peak (the angle at `Oᵢ`
//! between `F − Oᵢ` and `dᵢ` exceeds `β + Kσ − β`) and the peak is outside `ABC` (else `F` would
//! lie in the flux triangle). Both gathers, linear and hierarchical, apply that same cut-off.

use super::beams::GlossyBeam;
use beam_math::glam::Vec3;

/// Glossy beams reach this many standard deviations past their specular cone.
pub const GLOSSY_REACH: f32 = 4.0;

/// Half-angles above this make a cone unbounded (every point is inside).
const WIDEST: f32 = 80.0 * core::f32::consts::PI / 180.0;

/// Slack added to every half-angle (radians) and apex offset (relative), against rounding.
const SLACK: f32 = 1e-4;

/// A circular cone: the points `p` with `∠(p − apex, axis) ≤ acos(cos)`; `cos = −1` holds all.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingCone {
    /// Apex.
    pub apex: Vec3,
    /// Unit axis.
    pub axis: Vec3,
    /// Cosine of the half-angle.
    pub cos: f32,
    /// Half-angle (radians).
    pub angle: f32,
    /// Its sine.
    pub sin: f32,
}

impl BoundingCone {
    /// The cone holding every point.
    pub const ALL: Self = Self { apex: Vec3::ZERO, axis: Vec3::Z, cos: -1.0, angle: core::f32::consts::PI, sin: 0.0 };

    /// True when it holds every point.
    #[must_use]
    pub fn is_unbounded(&self) -> bool {
        self.cos <= -1.0
    }

    /// The cone of half-angle `angle` about `axis` whose apex lies behind the ball of radius
    /// `radius` at `centre`, holding the ball.
    fn around(centre: Vec3, radius: f32, axis: Vec3, angle: f32) -> Self {
        let angle = (angle + SLACK).max(1e-3);
        if angle > WIDEST {
            return Self::ALL;
        }
        let back = radius * (1.0 + SLACK) / angle.sin() + SLACK * radius;
        Self { apex: centre - axis * back, axis, cos: angle.cos(), angle, sin: angle.sin() }
    }

    /// The bounding cone of `beam`'s support (see the module doc), glossy beams widened by
    /// [`GLOSSY_REACH`]`·σ`.
    #[must_use]
    pub fn of_beam(beam: &GlossyBeam) -> Self {
        let b = &beam.beam;
        let Some(axis) = (b.dirs[0] + b.dirs[1] + b.dirs[2]).try_normalize() else { return Self::ALL };
        let spread = b.dirs.iter().map(|d| axis.dot(*d).clamp(-1.0, 1.0).acos()).fold(0.0, f32::max);
        let centre = (b.origins[0] + b.origins[1] + b.origins[2]) / 3.0;
        let radius = b.origins.iter().map(|o| (*o - centre).length()).fold(0.0, f32::max);
        Self::around(centre, radius, axis, spread + GLOSSY_REACH * beam.sigma)
    }

    /// A cone holding every cone of `cones`.
    #[must_use]
    pub fn enclosing(cones: &[Self]) -> Self {
        if cones.iter().any(Self::is_unbounded) || cones.is_empty() {
            return Self::ALL;
        }
        let Some(axis) = cones.iter().map(|c| c.axis).sum::<Vec3>().try_normalize() else { return Self::ALL };
        let angle = cones.iter().map(|c| axis.dot(c.axis).clamp(-1.0, 1.0).acos() + c.angle).fold(0.0, f32::max);
        let angle = angle + SLACK;
        if angle > WIDEST {
            return Self::ALL;
        }
        // Apex behind the centroid of the apexes, far enough back that every apex lies inside.
        let centre = cones.iter().map(|c| c.apex).sum::<Vec3>() / cones.len() as f32;
        let back = cones
            .iter()
            .map(|c| {
                let q = c.apex - centre;
                let along = q.dot(axis);
                let off = (q - along * axis).length();
                off / angle.tan() - along
            })
            .fold(0.0, f32::max);
        let extent = cones.iter().map(|c| (c.apex - centre).length()).fold(0.0, f32::max);
        let apex = centre - axis * (back * (1.0 + SLACK) + SLACK * extent);
        Self { apex, axis, cos: angle.cos(), angle, sin: angle.sin() }
    }

    /// True when `p` lies in the cone.
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        let q = p - self.apex;
        q.dot(self.axis) >= q.length() * self.cos
    }

    /// True when `p` may lie within distance `r` of the cone: it lies in the cone of the same
    /// angle with its apex moved back by `r / sin(angle)`, which holds every ball of radius `r`
    /// centred in this one. `r = 0`: [`BoundingCone::contains`].
    #[must_use]
    pub fn contains_within(&self, p: Vec3, r: f32) -> bool {
        if r <= 0.0 || self.is_unbounded() {
            return self.contains(p);
        }
        let q = p - (self.apex - self.axis * (r / self.sin));
        q.dot(self.axis) >= q.length() * self.cos
    }
}

/// A node of the hierarchy: its cone and either two children or a run of beams.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeNode {
    /// Holds the cones of all its beams.
    pub cone: BoundingCone,
    /// Inner node: index of its second child (the first follows it); leaf: first beam.
    pub right_or_first: u32,
    /// Beams of a leaf; 0 for an inner node.
    pub count: u32,
}

/// Beams per leaf at most.
const LEAF: usize = 4;

/// The cone hierarchy over a set of beams, in depth-first order; the beams it was built over are
/// reordered so that each leaf's beams are contiguous.
#[derive(Clone, Debug, Default)]
pub struct ConeTree {
    /// Nodes, the root first.
    pub nodes: Vec<ConeNode>,
    /// Each beam's own cone, in the reordered beam order.
    pub cones: Vec<BoundingCone>,
}

impl ConeTree {
    /// Build over `beams` (reordered in place): median splits along the widest spread of the beams'
    /// cone apexes and axes.
    #[must_use]
    pub fn build(beams: &mut [GlossyBeam]) -> Self {
        let mut items: Vec<(GlossyBeam, BoundingCone)> = beams.iter().map(|b| (*b, BoundingCone::of_beam(b))).collect();
        let mut tree = Self::default();
        if !items.is_empty() {
            let scale = items
                .iter()
                .filter(|(_, c)| !c.is_unbounded())
                .map(|(_, c)| c.apex.abs().max_element())
                .fold(1.0f32, f32::max);
            tree.split(&mut items, 0, scale);
        }
        for (slot, (beam, cone)) in beams.iter_mut().zip(&items) {
            *slot = *beam;
            tree.cones.push(*cone);
        }
        tree
    }

    /// The subtree over `items` (beams from `first` on); returns its node index.
    fn split(&mut self, items: &mut [(GlossyBeam, BoundingCone)], first: usize, scale: f32) -> usize {
        let cones: Vec<BoundingCone> = items.iter().map(|i| i.1).collect();
        let index = self.nodes.len();
        self.nodes.push(ConeNode { cone: BoundingCone::enclosing(&cones), right_or_first: first as u32, count: 0 });
        if items.len() <= LEAF {
            self.nodes[index].count = items.len() as u32;
            return index;
        }
        // Sort key: apex position (scaled to the scene) and axis, along the widest of the six.
        let key = |c: &BoundingCone| -> [f32; 6] {
            let a = if c.is_unbounded() { Vec3::ZERO } else { c.apex / scale };
            [a.x, a.y, a.z, c.axis.x, c.axis.y, c.axis.z]
        };
        let spread = (0..6)
            .map(|k| {
                let (lo, hi) = cones
                    .iter()
                    .map(|c| key(c)[k])
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
                hi - lo
            })
            .enumerate()
            .fold((0, f32::NEG_INFINITY), |best, (k, s)| if s > best.1 { (k, s) } else { best })
            .0;
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |a, b| key(&a.1)[spread].total_cmp(&key(&b.1)[spread]));
        let (left, right) = items.split_at_mut(mid);
        self.split(left, first, scale);
        let r = self.split(right, first + mid, scale);
        self.nodes[index].right_or_first = r as u32;
        index
    }

    /// Visit, in beam order, every beam whose leaf's and ancestors' cones come within distance `r`
    /// of `p` (hold it, for `r = 0`): `visit(i)` with its index. Returns the nodes visited.
    pub fn for_each_near(&self, p: Vec3, r: f32, mut visit: impl FnMut(usize)) -> u32 {
        let mut stack = [0u32; 64];
        let mut sp = usize::from(!self.nodes.is_empty());
        let mut visited = 0;
        while sp > 0 {
            sp -= 1;
            let index = stack[sp] as usize;
            let node = &self.nodes[index];
            visited += 1;
            if !node.cone.contains_within(p, r) {
                continue;
            }
            if node.count > 0 {
                let first = node.right_or_first as usize;
                (first..first + node.count as usize).for_each(&mut visit);
            } else if sp + 2 <= stack.len() {
                // The second child first on the stack, so that the first is visited first.
                stack[sp] = node.right_or_first;
                stack[sp + 1] = index as u32 + 1;
                sp += 2;
            }
        }
        visited
    }
}
