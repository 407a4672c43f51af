//! The GPU layout: the 32-byte [`FlatNode`] (WGSL twin `BvhNode`) and the triangles copied in leaf
//! order (WGSL twin `BvhTriangle`), so a leaf's `right_or_first..+count` indexes the triangle buffer
//! directly, with the input index kept in `prim`.

use crate::{FlatBvh, FlatNode};
use beam_math::Triangle;
use bytemuck::{Pod, Zeroable};
use std::vec::Vec;

/// A triangle for the GPU.
///
/// Keep in sync with the WGSL twin in `beam-gpu/shaders/shared/bvh.wgsl`:
/// `struct BvhTriangle { v0: vec3<f32>, prim: u32, v1: vec3<f32>, pad1: u32, v2: vec3<f32>, pad2: u32 }`.
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

/// Node and triangle buffers ready for upload.
#[derive(Clone, Debug, Default)]
pub struct GpuBvh {
    /// Nodes, identical to the CPU layout.
    pub nodes: Vec<FlatNode>,
    /// Triangles in leaf order.
    pub triangles: Vec<GpuTriangle>,
}

impl GpuBvh {
    /// Convert a CPU BVH over `triangles`.
    #[must_use]
    pub fn new(bvh: &FlatBvh, triangles: &[Triangle]) -> Self {
        let triangles = bvh.prims.iter().map(|&p| GpuTriangle::new(&triangles[p as usize], p)).collect();
        Self { nodes: bvh.nodes.clone(), triangles }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BuildOptions;
    use beam_math::glam::Vec3;

    #[test]
    fn leaf_ranges_index_the_triangle_buffer() {
        let tris: Vec<Triangle> = (0..50)
            .map(|i| {
                Triangle::new(Vec3::splat(i as f32), Vec3::splat(i as f32) + Vec3::X, Vec3::splat(i as f32) + Vec3::Y)
            })
            .collect();
        let bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        let gpu = GpuBvh::new(&bvh, &tris);
        assert_eq!(gpu.node_bytes().len(), 32 * bvh.nodes.len());
        for n in gpu.nodes.iter().filter(|n| n.is_leaf()) {
            for k in n.right_or_first..n.right_or_first + n.count {
                let t = &gpu.triangles[k as usize];
                assert_eq!(t.v0, tris[t.prim as usize].v[0].to_array());
            }
        }
    }
}
