//! Bounding-cone culling split as 000 splits it (App. A; objects on the CPU, triangles on the GPU,
//! `shaders/beam_cull.wgsl`): the host keeps a beam's leaf blocks of the 8-wide BVH whose boxes
//! meet its cone ([`cone_blocks`]); the page's first pass turns each lane of each kept block into
//! a (beam, triangle) pair or a culled one, testing what [`ConeCull::keeps`] tests on the host.
//! The host writes 8 bytes per block of four triangles and tests no triangle; before, it tested
//! each one and wrote 8 bytes per pair kept.
//!
//! [`cone_blocks`]: beam_render::nonlinear::cone_blocks

use crate::buffers::{compute_pass, compute_pipeline, output, storage};
use crate::interface::{NONE, WORKGROUP_SIZE};
use crate::{Gpu, GpuError};
use beam_render::nonlinear::{ConeCull, Exclude};
use beam_scene::scene::Scene;
use bytemuck::{Pod, Zeroable};

/// How one beam culls the triangles of its blocks ([`ConeCull`], and what it skips).
///
/// WGSL twin: `BeamCull` in `shaders/beam_cull.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct BeamCull {
    /// The bounding cone's apex.
    pub apex: [f32; 3],
    /// Cosine of its half-angle.
    pub cos_angle: f32,
    /// Its unit axis.
    pub axis: [f32; 3],
    /// Sine of its half-angle.
    pub sin_angle: f32,
    /// The base's inner unit normal (the self-hit floor's).
    pub floor_normal: [f32; 3],
    /// The floor's height over the base's first corner.
    pub floor: f32,
    /// The base's first corner.
    pub base0: [f32; 3],
    /// 1 where the beam has a floor, else 0.
    pub has_floor: u32,
    /// The base's second corner.
    pub base1: [f32; 3],
    /// The scene triangle of the base, skipped.
    pub prim: u32,
    /// The base's third corner.
    pub base2: [f32; 3],
    /// Padding.
    pub pad: u32,
    /// A coarse face's patch (skipped): its first entry in the page's lists and its length.
    pub patch_list: [u32; 2],
    /// A coarse face's ring (hits within the self-hit distance are the surface meeting itself).
    pub ring_list: [u32; 2],
}

const _: () = assert!(size_of::<BeamCull>() == 112);

impl BeamCull {
    /// `cull` with `exclude`'s base triangle, its patch and ring at `patch` and `ring` of the lists.
    #[must_use]
    pub fn new(cull: &ConeCull, exclude: Exclude<'_>, patch: [u32; 2], ring: [u32; 2]) -> Self {
        let (apex, axis, cos_angle, sin_angle) = cull.spheres.terms();
        // Without a floor the shader reads neither the base nor the floor.
        let f = cull.floor.unwrap_or_default();
        Self {
            apex: apex.into(),
            cos_angle,
            axis: axis.into(),
            sin_angle,
            floor_normal: f.normal.into(),
            floor: f.floor,
            base0: f.base[0].into(),
            has_floor: u32::from(cull.floor.is_some()),
            base1: f.base[1].into(),
            prim: exclude.prim,
            base2: f.base[2].into(),
            pad: 0,
            patch_list: patch,
            ring_list: ring,
        }
    }
}

/// The cull pass and what it reads of the scene.
pub(super) struct GpuCull {
    pipeline: wgpu::ComputePipeline,
    /// The scene triangle in each lane of each block of the 8-wide BVH (`NONE` unused).
    block_prims: wgpu::Buffer,
    /// Per scene triangle: its bounding sphere's centre and radius.
    spheres: wgpu::Buffer,
}

/// A page's culling: per beam on it, its [`BeamCull`], and the patches and rings they point into.
#[derive(Default)]
pub(super) struct PageCulls {
    pub culls: Vec<BeamCull>,
    pub lists: Vec<u32>,
}

impl PageCulls {
    /// Add a beam culled by `cull` with `exclude`.
    pub(super) fn push(&mut self, cull: &ConeCull, exclude: Exclude<'_>) {
        let mut list = |l: &[u32]| {
            let at = [self.lists.len() as u32, l.len() as u32];
            self.lists.extend_from_slice(l);
            at
        };
        let (patch, ring) = (list(exclude.patch), list(exclude.ring));
        self.culls.push(BeamCull::new(cull, exclude, patch, ring));
    }
}

impl GpuCull {
    /// Compile the pass and upload `scene`'s blocks and bounding spheres.
    pub(super) fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let spheres: Vec<[f32; 4]> = (0..scene.triangles.len() as u32)
            .map(|i| {
                let (c, r) = scene.bounding_sphere(i);
                [c.x, c.y, c.z, r]
            })
            .collect();
        let block_prims: Vec<u32> = scene.wide.prims.iter().map(|&p| if p == u32::MAX { NONE } else { p }).collect();
        Ok(Self {
            pipeline: compute_pipeline(gpu, "beam_cull", "cull_triangles")?,
            block_prims: storage(gpu, "block triangles", &block_prims, wgpu::BufferUsages::empty()),
            spheres: storage(gpu, "bounding spheres", &spheres, wgpu::BufferUsages::empty()),
        })
    }

    /// Add to `encoder` the pass that makes the page's pairs (four per block of `blocks`, the
    /// count in `params`, `AtlasParams::pairs`) from a [`PageCulls`] uploaded (`culls`, `lists`);
    /// returns their buffer.
    pub(super) fn encode(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        (params, triangles, blocks): (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
        (culls, lists): (&wgpu::Buffer, &wgpu::Buffer),
        pairs: usize,
    ) -> wgpu::Buffer {
        let out = output(gpu, "pairs", (pairs * 8) as u64);
        let entries = [
            (0, params),
            (2, triangles),
            (4, blocks),
            (5, &self.block_prims),
            (6, culls),
            (7, lists),
            (8, &self.spheres),
            (9, &out),
        ];
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("beam_cull"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries.map(|(binding, b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }),
        });
        compute_pass(encoder, &self.pipeline, &group, pairs.div_ceil(WORKGROUP_SIZE as usize).max(1) as u32);
        out
    }
}
