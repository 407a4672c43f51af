//! Which triangle lies across each edge of a triangle soup: corners welded by their exact position,
//! so that the triangles of an indexed mesh find their neighbours whatever file they came from. The
//! silhouette edges of shadow beams (beam-cpu) are the edges whose two triangles face a point
//! differently; edges with one triangle (boundaries) or more than two (non-manifold) always count.

use beam_math::Triangle;
use beam_math::glam::Vec3;
use rustc_hash::FxHashMap;

/// [`Adjacency::across`] of an edge that only one triangle has.
pub const BOUNDARY: u32 = u32::MAX;

/// [`Adjacency::across`] of an edge that three or more triangles share.
pub const NON_MANIFOLD: u32 = u32::MAX - 1;

/// Neighbours of a triangle soup's triangles. Edge `k` of a triangle runs from its corner `k` to
/// corner `(k + 1) % 3`.
#[derive(Clone, Debug, Default)]
pub struct Adjacency {
    /// Per triangle, the welded index of each corner (equal positions, equal index).
    corners: Vec<[u32; 3]>,
    /// Per triangle and edge, the triangle across it, or [`BOUNDARY`] or [`NON_MANIFOLD`].
    across: Vec<[u32; 3]>,
    /// Per triangle, bit `k` set when the triangle across edge `k` runs it the same way (the two are
    /// oriented inconsistently).
    same_way: Vec<u8>,
}

/// A position's bits, with −0 and +0 as one.
fn key(v: Vec3) -> [u32; 3] {
    (v + Vec3::ZERO).to_array().map(f32::to_bits)
}

impl Adjacency {
    /// The neighbours of `triangles`.
    #[must_use]
    pub fn new(triangles: &[Triangle]) -> Self {
        let mut ids: FxHashMap<[u32; 3], u32> = FxHashMap::default();
        ids.reserve(triangles.len() / 2 + 3);
        let corners: Vec<[u32; 3]> = triangles
            .iter()
            .map(|t| {
                t.v.map(|v| {
                    let next = ids.len() as u32;
                    *ids.entry(key(v)).or_insert(next)
                })
            })
            .collect();
        drop(ids);
        // First triangle and edge of each undirected edge, and how many more have it.
        let mut first: FxHashMap<(u32, u32), (u32, u8, u32)> = FxHashMap::default();
        first.reserve(triangles.len() * 3 / 2 + 3);
        let mut across = vec![[BOUNDARY; 3]; triangles.len()];
        let mut same_way = vec![0u8; triangles.len()];
        for (f, c) in corners.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (c[k], c[(k + 1) % 3]);
                if a == b {
                    continue;
                }
                let entry = first.entry((a.min(b), a.max(b))).or_insert((f as u32, k as u8, 0));
                entry.2 += 1;
                let (g, l, count) = *entry;
                match count {
                    1 => {}
                    2 => {
                        across[f][k] = g;
                        across[g as usize][l as usize] = f as u32;
                        // Same way when both run from the smaller corner or both from the larger.
                        let g_from = corners[g as usize][l as usize];
                        if g_from == a {
                            same_way[f] |= 1 << k;
                            same_way[g as usize] |= 1 << l;
                        }
                    }
                    _ => {}
                }
            }
        }
        // Edges of three or more triangles: every holder.
        for (f, c) in corners.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (c[k], c[(k + 1) % 3]);
                if a != b && first.get(&(a.min(b), a.max(b))).is_some_and(|e| e.2 > 2) {
                    across[f][k] = NON_MANIFOLD;
                }
            }
        }
        Self { corners, across, same_way }
    }

    /// The triangle across edge `k` of triangle `f` ([`BOUNDARY`], [`NON_MANIFOLD`] or an index).
    #[must_use]
    #[inline]
    pub fn across(&self, f: u32, k: usize) -> u32 {
        self.across[f as usize][k]
    }

    /// True when the triangle across edge `k` of `f` runs that edge in the same direction as `f`.
    #[must_use]
    #[inline]
    pub fn same_way(&self, f: u32, k: usize) -> bool {
        self.same_way[f as usize] & (1 << k) != 0
    }

    /// The welded corner indices of triangle `f`.
    #[must_use]
    #[inline]
    pub fn corners(&self, f: u32) -> [u32; 3] {
        self.corners[f as usize]
    }

    /// Number of triangles.
    #[must_use]
    pub fn len(&self) -> usize {
        self.corners.len()
    }

    /// True for no triangles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.corners.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tetrahedron_is_closed_and_a_flipped_face_or_a_fin_is_found() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let tri = |a: usize, b: usize, c: usize| Triangle::new(p[a], p[b], p[c]);
        // Outward counter-clockwise faces.
        let mut tris = vec![tri(0, 2, 1), tri(0, 1, 3), tri(1, 2, 3), tri(0, 3, 2)];
        let adj = Adjacency::new(&tris);
        for f in 0..4 {
            for k in 0..3 {
                let g = adj.across(f, k);
                assert!(g < 4 && g != f, "{f} {k}: {g}");
                assert!(!adj.same_way(f, k));
            }
        }
        // One face flipped: its three edges run the same way as its neighbours'.
        tris[3] = tri(0, 2, 3);
        let adj = Adjacency::new(&tris);
        assert!((0..3).all(|k| adj.same_way(3, k)));
        // A fin on edge 0–1: three triangles there.
        tris.push(Triangle::new(p[0], p[1], Vec3::new(0.5, -1.0, 0.0)));
        let adj = Adjacency::new(&tris);
        assert_eq!(adj.across(4, 0), NON_MANIFOLD);
        assert_eq!(adj.across(4, 1), BOUNDARY);
        assert_eq!((0..3).filter(|&k| adj.across(0, k) == NON_MANIFOLD).count(), 1);
    }
}
