//! One atlas page on the GPU (`shaders/beam_atlas.wgsl`, `shaders/beam_texels.wgsl`): the bounding
//! triangles of its (beam, triangle) pairs, then the nearest hit of every texel of its beams'
//! regions, by compute where the device has 64-bit atomics or else by 000's draws and a gather,
//! read back as the beams' hit textures. `atlas.rs` packs the beams onto pages.

use super::GpuBeams;
use super::level::{Appended, LevelCounts, LevelKeep, LevelPage, host_points};
use super::page_inputs::PageInputs;
use crate::GpuError;
use crate::buffers::{buffer_entry, compute_pass_timed, map_with, output, readback, storage, uniform, view_entry};
use crate::interface::WORKGROUP_SIZE;
use crate::texels::texture_2d;
use crate::timestamps::PassTimer;
use beam_render::nonlinear::{BeamJob, BeamTexture, TexelHit, region_texels};
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

impl GpuBeams<'_> {
    /// Render one page of `rows` rows from its `inputs`: its beams with their (beam on the page,
    /// block) pairs, made (beam, triangle) pairs by the cull pass (four per block, those of beam
    /// `i` at `inputs.ranges[i]`), the nearest hits by compute where this renderer can (else by
    /// draws). `unpack` reads, where the readback is mapped, the regions' texels (beam `i`'s from
    /// `inputs.firsts[i]` on, row by row, [`region_texels`]; each texel as [`Self::unpack`] reads
    /// it), and per beam the triangles
    /// kept and the texels tested. With `keep` (per beam: its first texel in the level's radiance,
    /// its face's scene triangle and its index in the level; whether to read every texel back all
    /// the same; the triangles' kinds), the level-points pass makes the page's points
    /// ([`super::level`]), returned with their counts, and `unpack` is handed the texels only if
    /// asked for (else none).
    pub(super) fn render_page<T>(
        &self,
        inputs: &PageInputs,
        rows: u32,
        keep: Option<&LevelKeep<'_>>,
        unpack: impl FnOnce(&[[u32; 2]], &[Counters]) -> T,
    ) -> Result<(T, Option<KeptPage>), GpuError> {
        let device = &self.gpu.device;
        let (beam_buffer, beam_count, pair_count) = (&inputs.beams, inputs.ranges.len(), inputs.pairs);
        let (ranges, firsts, first_texels) = (&inputs.ranges, &inputs.firsts, &inputs.first_texels);
        let params =
            AtlasParams { size: [self.page as f32, rows as f32], extent: self.extent, pairs: pair_count as u32 };
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
            self.level.encode(self.gpu, &mut encoder, &page, keep)
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
            self.add_times(|t| t.atlas_pass_seconds.iter_mut().zip(&passes).for_each(|(a, s)| *a += s));
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
    #[allow(clippy::too_many_arguments)]
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
        let texture = |format, usage| texture_2d(self.gpu, "atlas", (self.page, rows), format, usage);
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

impl GpuBeams<'_> {
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
