//! The GPU layout: the 32-byte [`FlatNode`] (WGSL twin `BvhNode`) and the triangles copied in leaf
//! order (WGSL twin `BvhTriangle`), so a leaf's `right_or_first..+count` indexes the triangle buffer
//! directly, with the input index kept in `prim`; and the bound on the WGSL traversal's stack
//! ([`GPU_STACK_SIZE`], [`stack_entries`]) that [`GpuBvh::new`] checks every tree against.

use crate::{FlatBvh, FlatNode};
use beam_math::Triangle;
use bytemuck::{Pod, Zeroable};
use core::fmt;
use std::vec::Vec;

/// Entries of the traversal stack of `trace_ray` (`beam-gpu/shaders/lib/trace.wgsl`, where it is
/// `TRAVERSAL_STACK`, generated from this constant by `beam_gpu::interface`): a private array of 64
/// `u32` per invocation.
///
/// A tree needs its depth + 1 entries ([`stack_entries`]). Real scenes need far fewer (Sponza 23,
/// Šibenik 24, the conference room 28, the built-ins at most 19), but the builder makes trees up to
/// `MAX_SPLIT_DEPTH + ⌈log2 n⌉` = 96 + ⌈log2 n⌉ deep over degenerate meshes, and
/// [`GpuBvh::new`] refuses those rather than make every invocation carry a private array twice the
/// size (128 entries would hold every tree the builder makes; on an H100 they were no faster).
pub const GPU_STACK_SIZE: usize = 64;

/// Why a tree cannot go to the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpuBvhError {
    /// The WGSL traversal would need `entries` stack entries (the tree's depth + 1, see
    /// [`stack_entries`]), more than its `limit` ([`GPU_STACK_SIZE`]).
    TooDeep {
        /// Depth of the deepest leaf (the root is at depth 0).
        depth: usize,
        /// Stack entries the traversal needs at most.
        entries: usize,
        /// Stack entries it has.
        limit: usize,
    },
}

impl fmt::Display for GpuBvhError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::TooDeep { depth, entries, limit } => write!(
                f,
                "BVH too deep for the GPU: depth {depth} needs {entries} traversal stack entries, WGSL has {limit}"
            ),
        }
    }
}

impl std::error::Error for GpuBvhError {}

/// A triangle for the GPU.
///
/// WGSL twin: `BvhTriangle` in `beam-gpu/shaders/shared/bvh.wgsl` (layouts compared by
/// `beam_gpu::interface`'s tests).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuTriangle {
    /// Vertex 0.
    pub v0: [f32; 3],
    /// Index of the triangle in the input slice.
    pub prim: u32,
    /// Vertex 1.
    pub v1: [f32; 3],
    /// Padding to the WGSL `vec3` alignment.
    pub pad1: u32,
    /// Vertex 2.
    pub v2: [f32; 3],
    /// Padding to the WGSL `vec3` alignment.
    pub pad2: u32,
}

const _: () = assert!(size_of::<GpuTriangle>() == 48);

impl GpuTriangle {
    /// Triangle `t`, input index `prim`.
    #[must_use]
    pub fn new(t: &Triangle, prim: u32) -> Self {
        Self { v0: t.v[0].to_array(), prim, v1: t.v[1].to_array(), pad1: 0, v2: t.v[2].to_array(), pad2: 0 }
    }
}

/// Node and triangle buffers ready for upload, of a tree whose traversal fits the GPU's stack.
#[derive(Clone, Debug, Default)]
pub struct GpuBvh {
    nodes: Vec<FlatNode>,
    triangles: Vec<GpuTriangle>,
}

impl GpuBvh {
    /// Convert a CPU BVH over `triangles`; [`GpuBvhError::TooDeep`] when its traversal needs more
    /// than [`GPU_STACK_SIZE`] stack entries.
    pub fn new(bvh: &FlatBvh, triangles: &[Triangle]) -> Result<Self, GpuBvhError> {
        let entries = stack_entries(bvh);
        if entries > GPU_STACK_SIZE {
            return Err(GpuBvhError::TooDeep { depth: entries - 1, entries, limit: GPU_STACK_SIZE });
        }
        let triangles = bvh.prims.iter().map(|&p| GpuTriangle::new(&triangles[p as usize], p)).collect();
        Ok(Self { nodes: bvh.nodes.clone(), triangles })
    }

    /// Nodes, identical to the CPU layout.
    #[must_use]
    pub fn nodes(&self) -> &[FlatNode] {
        &self.nodes
    }

    /// Triangles in leaf order.
    #[must_use]
    pub fn triangles(&self) -> &[GpuTriangle] {
        &self.triangles
    }

    /// The node buffer as bytes.
    #[must_use]
    pub fn node_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.nodes)
    }

    /// The triangle buffer as bytes.
    #[must_use]
    pub fn triangle_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.triangles)
    }
}

/// The most entries the WGSL traversal (`trace_ray`) holds on its stack for any ray through `bvh`:
/// the depth of its deepest leaf + 1 (0 for an empty tree).
///
/// `trace_ray` pushes the root, then pops a node and, for an inner node, pushes the children its
/// ray enters (the farther first). A pending entry is a child of a popped node; when an entry is
/// popped, the children pushed after it have been popped with all their subtrees, so after popping
/// a node at depth `d` at most one entry per ancestor is pending (the sibling of the path at
/// depths 1..=d): `d` entries. Pushing both children of an inner node makes `d + 2`, and inner
/// nodes lie at depth at most `depth − 1`: `depth + 1`. A ray that enters every box along the path
/// to the deepest leaf, always nearer to the path's child than to its sibling, reaches it.
#[must_use]
pub fn stack_entries(bvh: &FlatBvh) -> usize {
    if bvh.nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut pending = vec![(0usize, 0usize)];
    while let Some((i, depth)) = pending.pop() {
        let n = &bvh.nodes[i];
        deepest = deepest.max(depth);
        if !n.is_leaf() {
            pending.push((i + 1, depth + 1));
            pending.push((n.right_or_first as usize, depth + 1));
        }
    }
    deepest + 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BuildOptions, TreeStats};
    use beam_math::glam::Vec3;

    fn soup(n: usize) -> Vec<Triangle> {
        (0..n)
            .map(|i| {
                let c = Vec3::new((i * 7 % 13) as f32, (i * 5 % 11) as f32, (i * 3 % 7) as f32);
                Triangle::new(c, c + Vec3::X, c + Vec3::Y)
            })
            .collect()
    }

    #[test]
    fn leaf_ranges_index_the_triangle_buffer() {
        let tris: Vec<Triangle> = (0..50)
            .map(|i| {
                Triangle::new(Vec3::splat(i as f32), Vec3::splat(i as f32) + Vec3::X, Vec3::splat(i as f32) + Vec3::Y)
            })
            .collect();
        let bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        let gpu = GpuBvh::new(&bvh, &tris).unwrap();
        assert_eq!(gpu.node_bytes().len(), 32 * bvh.nodes.len());
        for n in gpu.nodes.iter().filter(|n| n.is_leaf()) {
            for k in n.right_or_first..n.right_or_first + n.count {
                let t = &gpu.triangles[k as usize];
                assert_eq!(t.v0, tris[t.prim as usize].v[0].to_array());
            }
        }
    }

    /// The largest stack `trace_ray`'s push and pop discipline reaches on `bvh` when every box is
    /// entered and `nearer_first(node)` says whether the node's left child is the nearer one.
    fn wgsl_stack_peak(bvh: &FlatBvh, nearer_first: &mut impl FnMut(usize) -> bool) -> usize {
        // As lib/trace.wgsl: push the root; pop; for an inner node push the farther child, then
        // the nearer.
        let mut stack = vec![0usize];
        let mut peak = 1;
        while let Some(i) = stack.pop() {
            let n = &bvh.nodes[i];
            if n.is_leaf() {
                continue;
            }
            let (left, right) = (i + 1, n.right_or_first as usize);
            if nearer_first(i) {
                stack.extend([right, left]);
            } else {
                stack.extend([left, right]);
            }
            peak = peak.max(stack.len());
        }
        peak
    }

    /// Subtree heights, to put the deeper child first (the order that fills the stack most).
    fn heights(bvh: &FlatBvh) -> Vec<usize> {
        let mut h = vec![0; bvh.nodes.len()];
        // Children follow their parents in the depth-first layout.
        for i in (0..bvh.nodes.len()).rev() {
            let n = &bvh.nodes[i];
            if !n.is_leaf() {
                h[i] = 1 + h[i + 1].max(h[n.right_or_first as usize]);
            }
        }
        h
    }

    #[test]
    fn stack_entries_bound_the_wgsl_traversal_exactly() {
        for n in [1, 2, 3, 5, 8, 17, 40, 100] {
            let tris = soup(n);
            for max_leaf in [1, 4] {
                let bvh = FlatBvh::build(&tris, &BuildOptions { max_leaf, ..BuildOptions::sah() });
                let depth = TreeStats::of(&bvh).depth;
                assert_eq!(stack_entries(&bvh), depth + 1, "{n} triangles");
                // Any order stays within the bound ...
                let mut s = n as u32;
                let mut random = |_: usize| {
                    s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                    s >> 31 == 1
                };
                for _ in 0..50 {
                    assert!(wgsl_stack_peak(&bvh, &mut random) <= stack_entries(&bvh));
                }
                // ... and the deeper child first reaches it.
                let h = heights(&bvh);
                let mut deeper_first = |i: usize| h[i + 1] >= h[bvh.nodes[i].right_or_first as usize];
                assert_eq!(wgsl_stack_peak(&bvh, &mut deeper_first), stack_entries(&bvh), "{n} triangles");
            }
        }
        assert_eq!(stack_entries(&FlatBvh::default()), 0);
    }

    #[test]
    fn a_tree_deeper_than_the_stack_is_refused() {
        // A chain: each inner node has a leaf on the right and the rest on the left.
        let tris = soup(GPU_STACK_SIZE + 1);
        let chain = |m: usize| {
            let inner = m - 1;
            let mut nodes = Vec::new();
            for k in 0..inner {
                nodes.push(FlatNode { min: [0.0; 3], right_or_first: (2 * inner - k) as u32, max: [1.0; 3], count: 0 });
            }
            for j in 0..m {
                nodes.push(FlatNode { min: [0.0; 3], right_or_first: j as u32, max: [1.0; 3], count: 1 });
            }
            FlatBvh { nodes, prims: (0..m as u32).rev().collect(), degenerate: 0, input_triangles: m }
        };
        let fits = chain(GPU_STACK_SIZE);
        assert_eq!(TreeStats::of(&fits).depth, GPU_STACK_SIZE - 1);
        assert!(GpuBvh::new(&fits, &tris).is_ok());
        let deep = chain(GPU_STACK_SIZE + 1);
        let err = GpuBvh::new(&deep, &tris).unwrap_err();
        assert_eq!(
            err,
            GpuBvhError::TooDeep { depth: GPU_STACK_SIZE, entries: GPU_STACK_SIZE + 1, limit: GPU_STACK_SIZE }
        );
        assert!(err.to_string().contains("too deep"));
    }
}
