//! The candidate occluders of a tile of shade points, per area light and per block of the tile
//! (see [`super::shaft`]): gathered once through the BVH for the tile's shaft, then filtered by each
//! block's own shaft, so that a shadow beam from a point of a block splits only at triangles that
//! can lie between it and the light.

use super::packet::Packet;
use super::shaft::{Shaft, gather};
use crate::scene::{Light, Scene};
use beam_math::Aabb;
use beam_math::glam::Vec3;

/// Blocks per tile side (a tile of [`super::TILE`]² pixels has blocks of `TILE / BLOCKS` pixels a side).
pub(crate) const BLOCKS: usize = 4;

/// The candidates of one block for one light.
#[derive(Clone, Copy, Debug)]
struct Block {
    /// Box of the block's shade points: the candidates hold for any point inside it.
    points: Aabb,
    start: u32,
    end: u32,
}

/// Candidate occluders of a tile, per light and block. Empty until [`TileShadows::build`].
#[derive(Default)]
pub(crate) struct TileShadows {
    /// `blocks[light * BLOCKS² + block]`.
    blocks: Vec<Block>,
    /// The blocks' candidates, four to a packet.
    packets: Vec<Packet>,
    /// One block's candidates with their sort keys.
    block: Vec<(u32, u32)>,
    /// BVH nodes tested by the tiles' shafts.
    pub(crate) bvh_steps: u64,
    /// Shafts traced (one a tile and area light).
    pub(crate) shafts: u64,
}

impl TileShadows {
    /// Forget the last tile: every point falls back to its own BVH traversal.
    pub(crate) fn clear(&mut self) {
        self.blocks.clear();
    }

    /// Gather the candidates for the shade points `points` (each with its block index,
    /// `< BLOCKS²`), for every area light of `scene` that faces them.
    pub(crate) fn build(&mut self, scene: &Scene, points: &[(usize, Vec3)]) {
        self.blocks.clear();
        self.packets.clear();
        let empty = Block { points: Aabb::EMPTY, start: 0, end: 0 };
        for light in &scene.lights {
            let base = self.blocks.len();
            self.blocks.resize(base + BLOCKS * BLOCKS, empty);
            if matches!(light, Light::Point { .. }) {
                continue;
            }
            let (polygon, ln, center) = (light.polygon(), light.normal(), light.center());
            let mut tile = Aabb::EMPTY;
            for &(block, p) in points {
                if ln.dot(p - center) > 0.0 {
                    let b = &mut self.blocks[base + block].points;
                    *b = b.grow(p);
                    tile = tile.grow(p);
                }
            }
            if !tile.is_valid() {
                continue;
            }
            let tris = &scene.triangles;
            for block in &mut self.blocks[base..] {
                if !block.points.is_valid() {
                    continue;
                }
                let shaft = Shaft::new(&block.points, &polygon, ln);
                self.shafts += 1;
                self.bvh_steps += gather(&scene.bvh, tris, &shaft, &mut self.block);
                block.start = self.packets.len() as u32;
                for chunk in self.block.chunks(4) {
                    let mut prims = [0; 4];
                    for (p, &(_, prim)) in prims.iter_mut().zip(chunk) {
                        *p = prim;
                    }
                    self.packets.push(Packet::new(tris, &prims[..chunk.len()]));
                }
                block.end = self.packets.len() as u32;
            }
        }
    }

    /// The candidate occluders between `p` and light `light`, when `p` lies in the box of block
    /// `block`'s shade points (any point there: the shaft bounds every segment from the box).
    pub(crate) fn candidates(&self, light: usize, block: usize, p: Vec3) -> Option<&[Packet]> {
        let b = self.blocks.get(light * BLOCKS * BLOCKS + block)?;
        (b.points.min.cmple(p).all() && p.cmple(b.points.max).all())
            .then(|| &self.packets[b.start as usize..b.end as usize])
    }
}
