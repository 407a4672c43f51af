//! The candidate occluders of a tile of shade points, per area light and per block of the tile
//! (see [`super::shaft`]): each block's shade points gather, through the BVH, the triangles that
//! can lie between one of them and the light, so that a shadow beam from a point of the block
//! splits only at those. A block whose points straddle a depth discontinuity (a column's edge in
//! front of a far wall) is cut in two along its box's longest axis first, so that neither half's
//! shaft spans the gap.

use super::packet::Packet;
use super::shaft::{MAX_CANDIDATES, Shaft, gather};
use super::silhouettes::{self, SilEdge, WindingBuilder};
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};
use beam_render::options::Occluders;
use beam_scene::scene::{Light, Scene};

/// Blocks per tile side (a tile of [`super::TILE`]² pixels has blocks of `TILE / BLOCKS` pixels a side).
pub(crate) const BLOCKS: usize = 4;

/// Clusters per light: two halves of each block.
const PER_LIGHT: usize = 2 * BLOCKS * BLOCKS;

/// A block is cut in two when its box's diagonal exceeds this fraction of its distance to the light.
const SPREAD: f32 = 0.1;

/// The candidates of one half of a block for one light.
#[derive(Clone, Copy, Debug)]
struct Cluster {
    /// Box of the cluster's shade points: the candidates hold for any point inside it.
    points: Aabb,
    /// Packets of the candidates, split one at a time.
    packets: (u32, u32),
    /// The candidates as edges, and those that reach out of a point's depth range, once a beam
    /// has asked for them ([`TileShadows::edges`]).
    edges: Option<((u32, u32), (u32, u32))>,
    /// How its shadow beams take the candidates.
    mode: Mode,
    /// Whether a candidate is a cut-out (`None` where it has no list of candidates).
    cut_outs: Option<bool>,
}

/// How a cluster's shadow beams take its candidates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Split by them one at a time.
    Split,
    /// By their edges, the winding pass (`shadow_beam/silhouette.rs`).
    Winding,
    /// Not decided yet: the next beam does both and decides by their work ([`TileShadows::decide`]).
    Probe,
    /// By shadow rays over the light: a beam of the cluster ran past its budget.
    Rays,
    /// Through the BVH, each beam by itself: the cluster's shaft gathered too many candidates.
    Walk,
}

/// The candidate occluders of a shade point for one light.
#[derive(Clone, Copy)]
pub(crate) struct Candidates {
    /// How its beams take them: split by them one at a time ([`TileShadows::packets`]), by their
    /// edges ([`TileShadows::edges`]), or otherwise.
    pub(crate) mode: Mode,
    /// Whether one of them is a cut-out (`None` where the cluster has no list of candidates and
    /// no one has said yet, [`TileShadows::set_cut_outs`]).
    pub(crate) cut_outs: Option<bool>,
    /// The box of the cluster's points.
    pub(crate) points: Aabb,
    /// The cluster's index, for [`TileShadows::decide`].
    pub(crate) cluster: usize,
}

/// How a block's points are cut in two: the ones with `p[axis] ≤ at` go to the first cluster.
#[derive(Clone, Copy, Debug)]
struct Cut {
    axis: usize,
    at: f32,
}

/// Candidate occluders of a tile, per light, block and cluster. Empty until [`TileShadows::build`].
#[derive(Default)]
pub(crate) struct TileShadows {
    /// `clusters[light · PER_LIGHT + block · 2 + half]`.
    clusters: Vec<Cluster>,
    /// Per block of the light being built, its points' box and cut.
    boxes: Vec<(Aabb, Cut)>,
    /// The clusters' candidates, four to a packet.
    packets: Vec<Packet>,
    /// One cluster's candidates with their sort keys.
    gathered: Vec<(u32, u32)>,
    /// One cluster's candidates.
    ids: Vec<u32>,
    /// The clusters' candidates as edges, and each light's plane to build them for.
    edges: Vec<SilEdge>,
    reaching: Vec<u32>,
    planes: Vec<silhouettes::Light>,
    builder: WindingBuilder,
    /// BVH nodes tested by the shafts.
    pub(crate) bvh_steps: u64,
    /// Shafts traced (one a cluster and area light).
    pub(crate) shafts: u64,
    /// Per light, how this tile starts, by how the ones before it in its row ended.
    carried: Vec<Carry>,
}

/// How a tile's clusters start for one light, by how those of the tile before it in its row ended.
#[derive(Clone, Copy, Debug)]
struct Carry {
    /// The mode the clusters take from the start (`None`: each decides afresh).
    mode: Option<Mode>,
    /// Tiles in a row that have taken it.
    taken: u32,
    /// Most tiles in a row that take it: [`MAX_CARRY`], doubled (up to [`MAX_BACKOFF`]) each time
    /// the sentinel of a sampled run sampled again.
    limit: u32,
    /// Whether the tile samples the light from the start in every cluster but its first (the
    /// sentinel), which decides whether the run of sampled tiles goes on.
    sentinel: bool,
}

impl Default for Carry {
    fn default() -> Self {
        Self { mode: None, taken: 0, limit: MAX_CARRY, sentinel: false }
    }
}

/// How a tile's clusters start, per light, from how those of the tile before it in its row ended:
/// the cost model's decisions carried to the neighbours, as they are within a cluster. Where at
/// least [`SAMPLED_SHARE`] of them sampled by rays, the next tile samples that light from the
/// start without gathering candidates (the shafts are then most of the cost); where every one
/// split or sampled, but for fewer than [`WINDING_SHARE`] that weighed edges, the next splits
/// without probing (a probe builds its cluster's edges, 25 µs on Sponza at 256², where they win
/// one probe in five). After [`MAX_CARRY`] tiles, one starts afresh, except after a
/// run of sampled tiles: there one cluster of the next tile goes first (the sentinel) and the others
/// sample; where the sentinel samples too (a light too large for any beam's budget, as on Sponza
/// under a light as wide as the building), the next run of sampled tiles is twice as long, up to
/// [`MAX_BACKOFF`], and otherwise the tile after it starts afresh.
const SAMPLED_SHARE: f32 = 0.75;
const WINDING_SHARE: f32 = 0.25;
const MAX_CARRY: u32 = 3;
const MAX_BACKOFF: u32 = 24;

impl TileShadows {
    /// Gather the candidates among `scene`'s triangles for the shade points `points` (each with
    /// its block index, `< BLOCKS²`), for every area light of `lights` that faces them. The lights
    /// from index `walk_from` on (a constant environment's faces, which enclose the scene, so that a
    /// shaft to one gathers about every triangle) get no shaft: their beams walk the BVH
    /// themselves ([`Mode::Walk`]).
    pub(crate) fn build(
        &mut self,
        scene: &Scene,
        (lights, walk_from): (&[Light], usize),
        points: &[(usize, Vec3)],
        occluders: Occluders,
    ) {
        // How this tile's clusters start, by how the last tile's ended.
        self.carried.resize(lights.len(), Carry::default());
        for (light, carried) in self.carried.iter_mut().enumerate() {
            let clusters = self.clusters.get(light * PER_LIGHT..(light + 1) * PER_LIGHT).unwrap_or(&[]);
            let ended = |m: Mode| clusters.iter().filter(|c| c.points.is_valid() && c.mode == m).count() as f32;
            let valid = clusters.iter().filter(|c| c.points.is_valid()).count();
            let sampled = valid > 0 && ended(Mode::Rays) >= SAMPLED_SHARE * valid as f32;
            if core::mem::take(&mut carried.sentinel) {
                // The last tile's first cluster decides whether the sampled run goes on.
                let on = clusters.iter().find(|c| c.points.is_valid()).is_some_and(|c| c.mode == Mode::Rays);
                carried.limit = if on { (2 * carried.limit).min(MAX_BACKOFF) } else { MAX_CARRY };
                (carried.mode, carried.taken) = if on { (Some(Mode::Rays), 1) } else { (None, 0) };
                continue;
            }
            if carried.mode == Some(Mode::Rays) && carried.taken >= carried.limit && valid > 0 {
                // A run of sampled tiles ends: one cluster of this tile tries beams first.
                carried.sentinel = true;
                continue;
            }
            let mode = if valid == 0 || carried.taken >= carried.limit {
                None
            } else if sampled {
                Some(Mode::Rays)
            } else if occluders == Occluders::Auto && ended(Mode::Winding) < WINDING_SHARE * valid as f32 {
                Some(Mode::Split)
            } else {
                None
            };
            carried.taken = if mode.is_some() { carried.taken + 1 } else { 0 };
            carried.mode = mode;
        }
        self.clusters.clear();
        self.packets.clear();
        self.edges.clear();
        self.reaching.clear();
        self.planes.clear();
        let empty = Cluster { points: Aabb::EMPTY, packets: (0, 0), edges: None, mode: Mode::Split, cut_outs: None };
        for (index, light) in lights.iter().enumerate() {
            let base = self.clusters.len();
            self.clusters.resize(base + PER_LIGHT, empty);
            let (ln, center) = (light.normal(), light.center());
            self.planes.push(silhouettes::Light { normal: ln, center });
            if matches!(light, Light::Point { .. }) {
                continue;
            }
            let polygon = light.polygon();
            let lit = |p: Vec3| ln.dot(p - center) > 0.0;
            // The blocks' boxes, and where to cut the spread ones.
            self.boxes.clear();
            self.boxes.resize(BLOCKS * BLOCKS, (Aabb::EMPTY, Cut { axis: 0, at: f32::INFINITY }));
            for &(block, p) in points.iter().filter(|&&(_, p)| lit(p)) {
                self.boxes[block].0 = self.boxes[block].0.grow(p);
            }
            for (b, cut) in &mut self.boxes {
                if b.is_valid() && b.extent().length() > SPREAD * ln.dot(b.center() - center) {
                    let e = b.extent();
                    let axis = if e.x >= e.y && e.x >= e.z {
                        0
                    } else if e.y >= e.z {
                        1
                    } else {
                        2
                    };
                    *cut = Cut { axis, at: b.center()[axis] };
                }
            }
            for &(block, p) in points.iter().filter(|&&(_, p)| lit(p)) {
                let cut = self.boxes[block].1;
                let c = &mut self.clusters[base + 2 * block + usize::from(p[cut.axis] > cut.at)].points;
                *c = c.grow(p);
            }
            let tris = &scene.triangles;
            let Carry { mode: carried, sentinel, .. } = self.carried[base / PER_LIGHT];
            let first = self.clusters[base..].iter().position(|c| c.points.is_valid());
            for (i, cluster) in self.clusters[base..].iter_mut().enumerate() {
                if !cluster.points.is_valid() {
                    continue;
                }
                if carried == Some(Mode::Rays) && !(sentinel && Some(i) == first) {
                    cluster.mode = Mode::Rays;
                    continue;
                }
                if index >= walk_from {
                    cluster.mode = Mode::Walk;
                    continue;
                }
                let shaft = Shaft::new(&cluster.points, &polygon, ln);
                self.shafts += 1;
                self.bvh_steps += gather(&scene.wide, tris, &shaft, &mut self.gathered);
                if self.gathered.len() > MAX_CANDIDATES {
                    // Too wide: its points walk the BVH themselves (until one runs past its budget).
                    cluster.mode = Mode::Walk;
                    continue;
                }
                self.ids.clear();
                self.ids.extend(self.gathered.iter().map(|&(_, prim)| prim));
                cluster.cut_outs = Some(scene.has_cut_outs() && self.ids.iter().any(|&p| scene.cut_out(p).is_some()));
                if occluders != Occluders::Split && carried != Some(Mode::Split) {
                    cluster.mode = if occluders == Occluders::Edges { Mode::Winding } else { Mode::Probe };
                }
                cluster.packets = pack(tris, &self.ids, &mut self.packets);
            }
        }
    }

    /// The candidate occluders between `p` and light `light`, when `p` lies in the box of one of
    /// block `block`'s clusters (any point there: the shaft bounds every segment from the box).
    pub(crate) fn candidates(&self, light: usize, block: usize, p: Vec3) -> Option<Candidates> {
        let first = light * PER_LIGHT + 2 * block;
        let i = (first..first + 2).find(|&i| {
            self.clusters.get(i).is_some_and(|c| c.points.min.cmple(p).all() && p.cmple(c.points.max).all())
        })?;
        let c = &self.clusters[i];
        Some(Candidates { mode: c.mode, cut_outs: c.cut_outs, points: c.points, cluster: i })
    }

    /// Cluster `cluster`'s candidates, four to a packet.
    pub(crate) fn packets(&self, cluster: usize) -> &[Packet] {
        &self.packets[range(self.clusters[cluster].packets)]
    }

    /// Cluster `cluster`'s candidates as edges and the candidates that reach out of some point's
    /// depth range (`render/silhouettes`), built the first time a beam asks: most clusters never
    /// do, since splitting decides them first (`light_beam.rs`).
    pub(crate) fn edges(&mut self, cluster: usize, triangles: &[Triangle]) -> (&[SilEdge], &[u32]) {
        let c = self.clusters[cluster];
        let (edges, reaching) = c.edges.unwrap_or_else(|| {
            self.ids.clear();
            let packets = &self.packets[range(c.packets)];
            self.ids.extend(packets.iter().flat_map(|q| q.prims[..q.len as usize].iter().copied()));
            let (edges0, reaching0) = (self.edges.len() as u32, self.reaching.len() as u32);
            let plane = &self.planes[cluster / PER_LIGHT];
            self.builder.build(triangles, &c.points, plane, &self.ids, &mut self.edges, &mut self.reaching);
            let built = ((edges0, self.edges.len() as u32), (reaching0, self.reaching.len() as u32));
            self.clusters[cluster].edges = Some(built);
            built
        });
        (&self.edges[range(edges)], &self.reaching[range(reaching)])
    }

    /// Settle how cluster `cluster`'s remaining beams take their candidates. Where its probe chose
    /// splitting and none of the tile's clusters has chosen edges for that light, the clusters
    /// still to probe split without probing: a probe builds its cluster's edges and weighs them,
    /// 12% of `foliage`'s render at 128², where edges decided 59 of 10,490 beams (6 now), and
    /// Sponza at 512² took 0.80 thread-seconds instead of 0.96.
    pub(crate) fn decide(&mut self, cluster: usize, mode: Mode) {
        let probed = self.clusters[cluster].mode == Mode::Probe;
        self.clusters[cluster].mode = mode;
        if probed && mode == Mode::Split {
            let light = &mut self.clusters[cluster / PER_LIGHT * PER_LIGHT..][..PER_LIGHT];
            if light.iter().all(|c| c.mode != Mode::Winding) {
                light.iter_mut().filter(|c| c.mode == Mode::Probe).for_each(|c| c.mode = Mode::Split);
            }
        }
    }

    /// Record whether a cut-out may hide the light from a point of cluster `cluster`.
    pub(crate) fn set_cut_outs(&mut self, cluster: usize, cut_outs: bool) {
        self.clusters[cluster].cut_outs = Some(cut_outs);
    }
}

/// The indices of a `(start, end)` range.
fn range(r: (u32, u32)) -> core::ops::Range<usize> {
    r.0 as usize..r.1 as usize
}

/// Pack `prims` four to a packet at the end of `packets`; their range there.
fn pack(triangles: &[Triangle], prims: &[u32], packets: &mut Vec<Packet>) -> (u32, u32) {
    let start = packets.len() as u32;
    packets.extend(prims.chunks(4).map(|chunk| Packet::new(triangles, chunk)));
    (start, packets.len() as u32)
}
