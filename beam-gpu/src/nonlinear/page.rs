//! One atlas page on the GPU (`shaders/beam_atlas.wgsl`, `shaders/beam_texels.wgsl`): the bounding
//! triangles of its (beam, triangle) pairs, then the nearest hit of every texel of its beams'
//! regions, by compute where the device has 64-bit atomics or else by 000's draws and a gather,
//! read back as the beams' hit textures. `atlas.rs` packs the beams onto pages.

use super::cull::{GpuCull, PageCulls};
use super::level::{Appended, GpuLevelPoints, LevelCounts, LevelKeep, LevelPage, host_points};
use super::page_inputs::PageInputs;
use super::times::SummedTimes;
use crate::buffers::{
    buffer_entry, checked, compute_pass_timed, compute_pipeline, map_with, output, readback, shader_module, storage,
    uniform, view_entry,
};
use crate::interface::{NONE, WORKGROUP_SIZE};
use crate::texels::texture_2d;
use crate::timestamps::PassTimer;
use crate::{Gpu, GpuError};
use beam_bvh::gpu::GpuTriangle;
use beam_render::nonlinear::{BeamJob, BeamTexture, ConeCull, TexelHit, cone_blocks, region_texels};
use beam_scene::scene::Scene;
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

/// Uniforms of the atlas pass.
///
/// WGSL twin: `AtlasParams` in `shaders/lib/atlas.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct AtlasParams {
    /// Page width and height in texels.
    pub size: [f32; 2],
    /// The scene's diagonal (self-hit distances and the depth mapping).
    pub extent: f32,
    /// (beam, scene triangle) pairs on the page.
    pub pairs: u32,
}

const _: () = assert!(size_of::<AtlasParams>() == 16);

/// Per beam of a page: scene triangles kept (not behind its base) and texels tested.
pub(super) type Counters = [u32; 2];

/// A page's points of a kept level ([`super::level`]): each dispatch's lists and their counts.
pub(super) type KeptPage = (Vec<Appended>, Vec<LevelCounts>);

/// The passes that render an atlas page, and what they read of the scene (its triangles, the
/// culling's blocks and spheres): made with the renderer, for its life; no state between pages.
pub(super) struct AtlasPages<'g> {
    pub(super) gpu: &'g Gpu,
    bound: wgpu::ComputePipeline,
    pipeline: wgpu::RenderPipeline,
    gather: wgpu::ComputePipeline,
    /// The nearest hits by compute, where the device has 64-bit atomics (and unless
    /// [`AtlasPages::rasterized`] asked for rasterization).
    texels: Option<wgpu::ComputePipeline>,
    /// The scene's triangles.
    triangles: wgpu::Buffer,
    /// The per-triangle half of bounding-cone culling.
    cull: GpuCull,
    /// Side of a page in texels.
    pub(super) side: u32,
    /// The scene's diagonal.
    extent: f32,
}

impl<'g> AtlasPages<'g> {
    /// Compile the passes and upload `scene`'s triangles; pages of up to 4096² texels (less where
    /// the adapter allows less).
    pub(super) fn new(gpu: &'g Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let module = shader_module(gpu, "beam_atlas")?;
        let bound = compute_pipeline(gpu, "beam_atlas", "bound_triangles")?;
        let gather = compute_pipeline(gpu, "beam_atlas", "gather_regions")?;
        let pipeline = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("beam_atlas"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("emit_bounding_triangle"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("intersect_texel"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: wgpu::TextureFormat::Rg32Uint,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let texels =
            Self::can_compute(gpu).then(|| compute_pipeline(gpu, "beam_texels", "nearest_hits")).transpose()?;
        let by_prim: Vec<GpuTriangle> =
            scene.triangles.iter().enumerate().map(|(i, t)| GpuTriangle::new(t, i as u32)).collect();
        let triangles = storage(gpu, "scene triangles", &by_prim, wgpu::BufferUsages::empty());
        // A power of two, so that Z-order packing of power-of-two squares fills it.
        let side = gpu.device.limits().max_texture_dimension_2d.clamp(32, 4096);
        Ok(Self {
            gpu,
            bound,
            pipeline,
            gather,
            texels,
            triangles,
            cull: GpuCull::new(gpu, scene)?,
            side: 1 << (31 - side.leading_zeros()),
            extent: scene.bounds().extent().length(),
        })
    }

    /// Whether `gpu` has the 64-bit atomics that finding the nearest hits by compute takes.
    pub(super) fn can_compute(gpu: &Gpu) -> bool {
        gpu.device.features().contains(wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    }

    /// Find the nearest hits by rasterization even where the device could find them by compute.
    pub(super) fn rasterized(&mut self) {
        self.texels = None;
    }

    /// Whether the nearest hits are found by compute.
    pub(super) fn by_compute(&self) -> bool {
        self.texels.is_some()
    }

    /// The scene triangles the GPU keeps for each of `jobs` after culling by the BVH's boxes on the
    /// host and triangle by triangle on the device, each with [`crate::interface::PAIR_NEAR`]
    /// where it is in the beam's ring; in the order of the beam's blocks. For checks against
    /// [`beam_render::nonlinear::cone_candidates`]; all the jobs as one page.
    pub(super) fn culled_triangles(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<Vec<u32>>, GpuError> {
        let (culls, blocks): (Vec<ConeCull>, Vec<Vec<u32>>) = jobs
            .par_iter()
            .map(|j| {
                let tb = j.beam.texel_beam();
                cone_blocks(scene, tb, &tb.s1_or_sn_bounds(), j.exclude)
            })
            .unzip();
        let mut page = PageCulls::default();
        for (cull, job) in culls.iter().zip(jobs) {
            page.push(cull, job.exclude);
        }
        let pairs: Vec<[u32; 2]> =
            blocks.iter().enumerate().flat_map(|(k, b)| b.iter().map(move |&b| [k as u32, b])).collect();
        let slots = pairs.len() * 4;
        let params = AtlasParams { size: [1.0; 2], extent: self.extent, pairs: slots as u32 };
        checked(self.gpu, || {
            let params = uniform(self.gpu, "atlas params", bytemuck::bytes_of(&params));
            let blocks_buffer = storage(self.gpu, "blocks", &pairs, wgpu::BufferUsages::empty());
            let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
            let buffers = (&params, &self.triangles, &blocks_buffer);
            let none = wgpu::BufferUsages::empty();
            let culls =
                (storage(self.gpu, "beam culls", &page.culls, none), storage(self.gpu, "lists", &page.lists, none));
            let out = self.cull.encode(self.gpu, &mut encoder, buffers, (&culls.0, &culls.1), slots);
            let readback = readback(self.gpu, (slots * 8) as u64);
            encoder.copy_buffer_to_buffer(&out, 0, readback.buffer(), 0, (slots * 8) as u64);
            self.gpu.submit([encoder.finish()]);
            map_with(self.gpu, readback, |bytes| {
                let got: Vec<[u32; 2]> = bytemuck::pod_collect_to_vec(&bytes[..slots * 8]);
                let mut kept = vec![Vec::new(); jobs.len()];
                for [k, prim] in got.into_iter().filter(|p| p[1] != NONE) {
                    kept[k as usize].push(prim);
                }
                kept
            })
        })
    }

    /// Render one page of `rows` rows from its `inputs`: its beams with their (beam on the page,
    /// block) pairs, made (beam, triangle) pairs by the cull pass (four per block, those of beam
    /// `i` at `inputs.ranges[i]`), the nearest hits by compute where this renderer can (else by
    /// draws). `unpack` reads, where the readback is mapped, the regions' texels (beam `i`'s from
    /// `inputs.firsts[i]` on, row by row, [`region_texels`]; each texel as [`Self::unpack`] reads
    /// it), and per beam the triangles
    /// kept and the texels tested. With `keep` (per beam: its first texel in the level's radiance,
    /// its face's scene triangle and its index in the level; whether to read every texel back all
    /// the same; the triangles' kinds), the level-points pass makes the page's points
    /// ([`super::level`], by `level`'s pass), returned with their counts, and `unpack` is handed
    /// the texels only if asked for (else none). The passes' times go to `times`.
    pub(super) fn render_page<T>(
        &self,
        (level, times): (&GpuLevelPoints, &SummedTimes),
        inputs: &PageInputs,
        rows: u32,
        keep: Option<&LevelKeep<'_>>,
        unpack: impl FnOnce(&[[u32; 2]], &[Counters]) -> T,
    ) -> Result<(T, Option<KeptPage>), GpuError> {
        let device = &self.gpu.device;
        let (beam_buffer, beam_count, pair_count) = (&inputs.beams, inputs.ranges.len(), inputs.pairs);
        let (ranges, firsts, first_texels) = (&inputs.ranges, &inputs.firsts, &inputs.first_texels);
        let params =
            AtlasParams { size: [self.side as f32, rows as f32], extent: self.extent, pairs: pair_count as u32 };
        let uniform = uniform(self.gpu, "atlas params", bytemuck::bytes_of(&params));
        let bounds = output(self.gpu, "bounding triangles", (pair_count * 16) as u64);
        let counters = storage(self.gpu, "counters", &vec![[0u32; 2]; beam_count], wgpu::BufferUsages::COPY_SRC);
        let texel_count = firsts.last().copied().unwrap_or(0);
        let texel_bytes = u64::from(texel_count) * 8;
        let dense = output(self.gpu, "region texels", texel_bytes);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("atlas") });
        let pair_buffer = self.cull.encode(
            self.gpu,
            &mut encoder,
            (&uniform, &self.triangles, &inputs.blocks),
            (&inputs.culls.0, &inputs.culls.1),
            pair_count,
        );
        let group = bind(
            device,
            &self.bound.get_bind_group_layout(0),
            &[(0, &uniform), (1, beam_buffer), (2, &self.triangles), (3, &pair_buffer), (4, &bounds), (6, &counters)],
        );
        let groups = pair_count.div_ceil(WORKGROUP_SIZE as usize).max(1) as u32;
        // The passes' own times on the GPU, where it has timestamp queries.
        let timer = PassTimer::new(self.gpu, if self.by_compute() { 2 } else { 3 });
        compute_pass_timed(&mut encoder, &self.bound, &group, groups, timer.as_ref().map(|t| t.compute(0)));
        match (&self.texels, &inputs.jobs) {
            (Some(texels), Some((jobs, count))) => {
                let groups = (*count).max(1);
                let group = bind(
                    device,
                    &texels.get_bind_group_layout(0),
                    &[
                        (0, &uniform),
                        (1, beam_buffer),
                        (2, &self.triangles),
                        (3, &pair_buffer),
                        (4, &bounds),
                        (5, &counters),
                        (6, first_texels),
                        (7, &dense),
                        (8, jobs),
                    ],
                );
                compute_pass_timed(&mut encoder, texels, &group, groups, timer.as_ref().map(|t| t.compute(1)));
            }
            _ => {
                let buffers =
                    PageBuffers { uniform: &uniform, beams: beam_buffer, pairs: &pair_buffer, bounds: &bounds };
                let outputs = (&counters, first_texels, &dense);
                self.draw_page(&mut encoder, buffers, outputs, ranges, rows, texel_count, timer.as_ref());
            }
        }
        // The level's points, where it is kept, made from the texels where they lie.
        let appended = keep.map(|keep| {
            let page = LevelPage {
                beams: (beam_buffer, beam_count),
                firsts: first_texels,
                texels: (&dense, texel_count),
                inverted: self.by_compute(),
            };
            level.encode(self.gpu, &mut encoder, &page, keep)
        });
        let texel_bytes = if keep.is_some_and(|k| !k.with_hits) { 0 } else { texel_bytes };
        let count_bytes = beam_count as u64 * 8;
        let level_bytes = appended.as_ref().map_or(0, |a| a.len() * size_of::<LevelCounts>()) as u64;
        let readback =
            readback(self.gpu, texel_bytes + count_bytes + level_bytes + timer.as_ref().map_or(0, PassTimer::bytes));
        let into = readback.buffer();
        if texel_bytes > 0 {
            encoder.copy_buffer_to_buffer(&dense, 0, into, 0, texel_bytes);
        }
        encoder.copy_buffer_to_buffer(&counters, 0, into, texel_bytes, count_bytes);
        for (k, a) in appended.iter().flatten().enumerate() {
            let at = texel_bytes + count_bytes + (k * size_of::<LevelCounts>()) as u64;
            encoder.copy_buffer_to_buffer(&a.counts, 0, into, at, size_of::<LevelCounts>() as u64);
        }
        if let Some(timer) = &timer {
            timer.copy_to(&mut encoder, into, texel_bytes + count_bytes + level_bytes);
        }
        self.gpu.submit([encoder.finish()]);
        let out = map_with(self.gpu, readback, |bytes| {
            let (texels, rest) = bytes.split_at(texel_bytes as usize);
            let (counts, rest) = rest.split_at(count_bytes as usize);
            let (level_counts, stamps) = rest.split_at(level_bytes as usize);
            let passes = PassTimer::seconds(self.gpu, stamps);
            // Compute's nearest hits are the second pass, as the draws are; no gather follows.
            times.add(|t| t.atlas_pass_seconds.iter_mut().zip(&passes).for_each(|(a, s)| *a += s));
            let level_counts: Vec<LevelCounts> = bytemuck::pod_collect_to_vec(level_counts);
            // Aligned as mapped ranges are; copied only if a backend mapped them otherwise.
            let unpacked = match (bytemuck::try_cast_slice(texels), bytemuck::try_cast_slice(counts)) {
                (Ok(t), Ok(c)) => unpack(t, c),
                _ => unpack(&bytemuck::pod_collect_to_vec(texels), &bytemuck::pod_collect_to_vec(counts)),
            };
            (unpacked, level_counts)
        })?;
        let (unpacked, level_counts) = out;
        Ok((unpacked, appended.map(|a| (a, level_counts))))
    }

    /// 000's way to the nearest hits, added to `encoder`: one draw per beam over its pairs
    /// (`ranges`) onto a page of `rows` rows, the depth test keeping each texel's nearest hit; then
    /// the regions' `texel_count` texels gathered from the page into `dense`, at the beams'
    /// `firsts`. Timed as passes 1 and 2 of `timer`.
    fn draw_page(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        page: PageBuffers<'_>,
        (counters, firsts, dense): (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
        ranges: &[(u32, u32)],
        rows: u32,
        texel_count: u32,
        timer: Option<&PassTimer>,
    ) {
        let device = &self.gpu.device;
        let texture = |format, usage| texture_2d(self.gpu, "atlas", (self.side, rows), format, usage);
        let hits = texture(
            wgpu::TextureFormat::Rg32Uint,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let depth = texture(wgpu::TextureFormat::Depth32Float, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let group = bind(
            device,
            &self.pipeline.get_bind_group_layout(0),
            &[
                (0, page.uniform),
                (1, page.beams),
                (2, &self.triangles),
                (3, page.pairs),
                (5, page.bounds),
                (6, counters),
            ],
        );
        let hit_view = hits.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("atlas"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &hit_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.map(|t| t.render(1)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            for (i, &(start, end)) in ranges.iter().enumerate() {
                if end > start {
                    pass.draw(3 * start..3 * end, i as u32..i as u32 + 1);
                }
            }
        }
        // The regions' texels gathered into one list.
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("atlas gather"),
            layout: &self.gather.get_bind_group_layout(0),
            entries: &[
                buffer_entry(1, page.beams),
                view_entry(7, &hit_view),
                buffer_entry(8, firsts),
                buffer_entry(9, dense),
            ],
        });
        let groups = texel_count.div_ceil(WORKGROUP_SIZE).max(1);
        compute_pass_timed(encoder, &self.gather, &group, groups, timer.map(|t| t.compute(2)));
    }

    /// The textures of the beams `members` of one page (`jobs[i]`) from the regions' `texels`,
    /// beam `k`'s row by row from `firsts[k]` on, and per-beam `counts`, as (job index, texture).
    /// A texel is (scene triangle + 1, bits of t), 0 for a miss; `inverted` (by compute,
    /// `beam_texels.wgsl`) each word's bits are inverted, zeroes still a miss. Without `texels`
    /// (a kept level's, not read back), textures without hits.
    pub(super) fn unpack(
        jobs: &[BeamJob<'_>],
        members: &[usize],
        firsts: &[u32],
        texels: Option<&[[u32; 2]]>,
        counts: &[Counters],
        inverted: bool,
    ) -> Result<Vec<(usize, BeamTexture)>, GpuError> {
        members
            .par_iter()
            .zip(firsts)
            .zip(counts)
            .map(|((&i, &first), &[kept, tested])| {
                let size = jobs[i].size;
                let (triangles_after_culling, texels_tested) = (kept, u64::from(tested));
                let Some(texels) = texels else {
                    let points = Vec::new();
                    return Ok((
                        i,
                        BeamTexture {
                            size,
                            hits: Vec::new(),
                            points,
                            fits: Vec::new(),
                            triangles_after_culling,
                            texels_tested,
                        },
                    ));
                };
                let region = texels
                    .get(first as usize..first as usize + region_texels(size) as usize)
                    .ok_or_else(|| GpuError::Internal("a region's texels were not read back"))?;
                let mut hits = vec![None; (size * size) as usize];
                let mut from = region.iter();
                for y in 0..size {
                    // Texels past the region's diagonal (x + y > size) belong to no beam.
                    for (x, &[prim, t]) in (0..(size + 1 - y).min(size)).zip(&mut from) {
                        let [prim, t] = if inverted && prim != 0 { [!prim, !t] } else { [prim, t] };
                        if prim > 0 {
                            hits[(y * size + x) as usize] = Some(TexelHit { prim: prim - 1, t: f32::from_bits(t) });
                        }
                    }
                }
                let tex = BeamTexture {
                    size,
                    hits,
                    points: Vec::new(),
                    fits: Vec::new(),
                    triangles_after_culling,
                    texels_tested,
                };
                Ok((i, tex))
            })
            .collect()
    }
}

impl AtlasPages<'_> {
    /// Into `textures` (a page's, in the order of its beams, without hits), the texels listed as
    /// [`HostTexel`](super::HostTexel)s in `host` (bytes as read back, unpacked where they are mapped) as their
    /// points, each texture's in texel order: the texels of a kept level that the host builds on
    /// ([`super::level`]).
    pub(super) fn unpack_host_texels(textures: &mut [(usize, BeamTexture)], host: &[u8]) -> Result<(), GpuError> {
        let sizes: Vec<u32> = textures.iter().map(|(_, t)| t.size).collect();
        for ((_, tex), points) in textures.iter_mut().zip(host_points(host, &sizes, |h| h.beam)?) {
            tex.points = points;
        }
        Ok(())
    }
}

/// A bind group of `layout` over buffers alone: `(binding, buffer)`.
fn bind(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, entries: &[(u32, &wgpu::Buffer)]) -> wgpu::BindGroup {
    let entries: Vec<_> = entries.iter().map(|&(binding, b)| buffer_entry(binding, b)).collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("atlas"), layout, entries: &entries })
}

/// A page's uniforms, beams, (beam, triangle) pairs and their bounding triangles on the GPU.
#[derive(Clone, Copy)]
struct PageBuffers<'a> {
    uniform: &'a wgpu::Buffer,
    beams: &'a wgpu::Buffer,
    pairs: &'a wgpu::Buffer,
    bounds: &'a wgpu::Buffer,
}
