//! Shadow beams split by a list of candidate occluders (a shaft's, see `tile_shadows`) instead of
//! a BVH walk: the order in which they are tried. Visibility does not depend on it, the work does:
//! each triangle splits the pieces left by the ones before it.

use super::ShadowBeam;
use crate::render::packet::{Packet, Projector};
use beam_math::Triangle;
use beam_math::glam::Vec2;
use beam_render::tolerance::DEPTH_EPS;

/// Occluders of the previous beam tried first, when it ended dark.
const HOT: usize = 8;

/// Packets of candidates sorted together ([`ShadowBeam::occlude_packets`]): a long list (a wide
/// shaft through a large scene) is sorted in windows, its largest triangles first, so that a beam
/// that ends dark early does not project the whole list first.
const WINDOW: usize = 128;

impl ShadowBeam<'_> {
    /// The projection of this beam, for [`Packet::survivors`].
    pub(crate) fn projector(&self) -> Projector {
        let f = &self.frame;
        Projector {
            apex: f.apex,
            u: f.u,
            v: f.v,
            normal: f.normal,
            distance: f.distance,
            apex_uv: self.apex_uv,
            near: DEPTH_EPS * f.distance,
            far: (1.0 - DEPTH_EPS) * f.distance,
            touch: self.touch * f.distance,
            origin: f.origin - f.apex,
            eps: self.eps,
        }
    }

    /// Split by the candidates of `packets`, until nothing of the light is left.
    ///
    /// When the previous beam traced this way (a neighbouring shade point) ended dark, the
    /// occluders that hit it go first: an umbra continues from one point to the next, and ends the
    /// beam before any other candidate is projected. Then, [`WINDOW`] packets at a time, the
    /// candidates that survive the packet test go largest first by their projection's area on
    /// the pieces' bounding rectangle (ties, and triangles reaching out of the depth range, in the
    /// candidates' order): the likelier to hide much of the light, they leave the smaller ones
    /// fewer pieces to split (on foliage, half the splits of the candidates' own order).
    pub(crate) fn occlude_packets(&mut self, packets: &[Packet], triangles: &[Triangle]) {
        let mut hot = [0u32; HOT];
        let n = self.hot.len().min(HOT);
        hot[..n].copy_from_slice(&self.hot[..n]);
        self.hot.clear();
        for &prim in &hot[..n] {
            if self.occlude(&triangles[prim as usize]) {
                self.hot.push(prim);
            }
            if self.finished() {
                return;
            }
        }
        let projector = self.projector();
        for window in packets.chunks(WINDOW) {
            let (lo, hi) = (self.lo, self.hi);
            self.order.clear();
            self.survivors.clear();
            for packet in window {
                self.stats.triangle_tests += u64::from(packet.len);
                let (order, survivors) = (&mut *self.order, &mut *self.survivors);
                packet.survivors(&projector, lo, hi, &mut |s| {
                    let key = s.projected.map_or(f32::INFINITY, |q| overlap_area(&q, lo, hi));
                    // Descending order: the key's bits above, the complemented index below.
                    order.push(u64::from(key.to_bits()) << 32 | u64::from(!(survivors.len() as u32)));
                    survivors.push(s);
                });
            }
            self.order.sort_unstable_by(|a, b| b.cmp(a));
            for k in 0..self.order.len() {
                let s = self.survivors[!(self.order[k] as u32) as usize];
                let hit = match s.projected {
                    Some(q) => self.occlude_projected(&q),
                    // Reaching out of the depth range: the packet tried the planes beside it.
                    None => self.occlude_tested(&triangles[s.prim as usize], true),
                };
                if hit && self.hot.len() < HOT {
                    self.hot.push(s.prim);
                }
                if self.finished() {
                    return;
                }
            }
        }
        // Not dark: the next beam starts with the largest candidates.
        self.hot.clear();
    }
}

/// The area of triangle `q` times the part of its bounding rectangle inside `[lo, hi]`: an
/// estimate of how much of that rectangle it covers.
fn overlap_area(q: &[Vec2; 3], lo: Vec2, hi: Vec2) -> f32 {
    let (a, b) = (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]));
    let inside = (b.min(hi) - a.max(lo)).max(Vec2::ZERO);
    let whole = (b - a).x * (b - a).y;
    (q[1] - q[0]).perp_dot(q[2] - q[0]).abs() * (inside.x * inside.y / whole.max(f32::MIN_POSITIVE))
}
