//! The nonlinear pipeline of 000 §3 (`shaders/beam_atlas.wgsl`): every beam of a tree level packed
//! into square regions of atlas pages, one draw per beam (the instance) over the scene triangles its
//! bounding cone keeps (pulled from a storage buffer by vertex index / 3); the vertex stage emits
//! each triangle's bounding triangle on the beam's region, the fragment stage intersects the
//! texel's ray with it, and the depth test keeps the nearest hit. A page takes no more beams, and no
//! more (beam, triangle) pairs or region texels, than one storage binding of the device holds. A
//! compute pass gathers each page's regions into one list (a triangular region fills under half of
//! its power-of-two square), read back as the beams' hit textures, which beam-cpu's beam tree
//! needs for the next level's beams. Where the device has 64-bit atomics, one compute pass
//! (`shaders/beam_texels.wgsl`, an invocation per texel) finds the same hits instead of the draws
//! and the gather: a compute GPU rasterizes on few of its cores, a software one on one thread. Rays (the eye's view, the reference's Whitted rays) go to the
//! compute ray tracer; the radiance flows up the tree on the GPU ([`GpuComposite`]): diffuse,
//! glossy and emissive points shaded by [`PointShader`] (area lights by stratified shadow rays,
//! where the CPU's default is exact), specular ones composited from their child beams, only the
//! pixels read back.

use super::beam::GpuBeam;
use super::composite::GpuComposite;
use super::eye::{GpuEye, KeptPoints};
use super::whitted::GpuWhitted;
use crate::buffers::{
    buffer_entry, checked, compute_pass_timed, compute_pipeline, map_with, max_binding, output, read_all,
    shader_module, storage, uniform, view_entry,
};
use crate::interface::{PAIR_NEAR, TEXEL_JOB_PAIRS, WORKGROUP_SIZE};
use crate::raytrace::{GpuHit, GpuRay, RayTracer};
use crate::shade::{PointShader, ShadeInput};
use crate::staging::{Slots, Staged, split_by_counts};
use crate::timestamps::PassTimer;
use crate::{Gpu, GpuError};
use beam_bvh::Hit;
use beam_bvh::gpu::{GpuBvh, GpuTriangle};
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_scene::BackendError;
use beam_scene::irradiance_map::IrradianceMap;
use beam_scene::nonlinear::{
    BeamJob, BeamRasterizer, BeamTexture, DeviceWaits, LevelRadiance, PointShading, RayQueries, SMesh, ShadePoint,
    TexelHit, cone_candidates, region_texels,
};
use beam_scene::options::{RenderOptions, Shading};
use beam_scene::scene::Scene;
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;
use std::cell::Cell;
use std::sync::Mutex;
use std::time::Instant;

/// Uniforms of the atlas pass.
///
/// WGSL twin: `AtlasParams` in `shaders/beam_atlas.wgsl` (layouts compared in [`crate::interface`]).
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

/// Where the GPU renderer spent its time, summed over calls.
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuTimes {
    /// Seconds in atlas passes: upload, draws and readback, waiting for the GPU.
    pub atlas_seconds: f64,
    /// Seconds on the CPU preparing them (beam quantities, bounding-cone culling, packing).
    pub prepare_seconds: f64,
    /// Seconds tracing rays on the GPU (the eye's view, the reference's Whitted rays).
    pub ray_seconds: f64,
    /// Seconds shading points (mirror and glass ones by Whitted rays past the tree) and compositing
    /// the beam tree on the GPU.
    pub shade_seconds: f64,
    /// Of the composite's, host seconds (not blocked on the device) following the Whitted rays of
    /// mirror and glass points past the tree's last level.
    pub whitted_host_seconds: f64,
    /// Atlas pages rendered.
    pub pages: u64,
    /// Beams drawn.
    pub beams: u64,
    /// Scene triangles drawn (vertex-stage bounding triangles computed).
    pub triangles: u64,
    /// Beam trees composited on the GPU (the others fell back to the CPU's composite).
    pub gpu_composites: u64,
    /// The GPU's own seconds in the atlas passes, by timestamp queries (all 0 where the device has
    /// none): bounding triangles, nearest hits (draws, or the compute pass), gather.
    pub atlas_pass_seconds: [f64; 3],
}

/// The GPU's beam renderer for one scene: its triangles uploaded, the atlas pipeline compiled.
pub struct GpuBeams<'g> {
    pub(super) gpu: &'g Gpu,
    bound: wgpu::ComputePipeline,
    pipeline: wgpu::RenderPipeline,
    gather: wgpu::ComputePipeline,
    /// The nearest hits by compute, where the device has 64-bit atomics (and unless
    /// [`GpuBeams::rasterized`] asked for rasterization).
    texels: Option<wgpu::ComputePipeline>,
    triangles: wgpu::Buffer,
    pub(super) tracer: RayTracer,
    /// The eye's view on the GPU.
    pub(super) eye: GpuEye,
    /// The eye's points its last view kept on the GPU, until the composite shades them.
    pub(super) kept: Mutex<Option<Vec<KeptPoints>>>,
    /// Shading on the GPU.
    shader: PointShader,
    /// The final composite on the GPU.
    composite: GpuComposite,
    /// The Whitted rays past the tree on the GPU.
    whitted: GpuWhitted,
    /// Shadow rays per area light and shade point.
    light_samples: u32,
    /// Most pairs a workgroup of the compute pass tests its texels against.
    job_pairs: u32,
    extent: f32,
    /// Side of an atlas page in texels.
    page: u32,
    times: Mutex<GpuTimes>,
}

/// Per beam of a page: scene triangles kept (not behind its base) and texels tested.
type Counters = [u32; 2];

/// Where a beam landed: its page and the corner of its region.
struct Placed {
    page: usize,
    x: u32,
    y: u32,
}

impl<'g> GpuBeams<'g> {
    /// `rays` traced on the GPU (in dispatches that fit its bindings), timed as ray time.
    fn trace(&self, rays: Vec<GpuRay>) -> Result<Vec<GpuHit>, GpuError> {
        let start = Instant::now();
        let out = checked(self.gpu, || self.tracer.trace(self.gpu, &rays));
        self.add_times(|t| t.ray_seconds += start.elapsed().as_secs_f64());
        out
    }

    /// Exact shading of `points` on the GPU: diffuse, glossy and emissive points by the shading
    /// pass; mirrors and glass by Whitted rays traced on the GPU in waves ([`GpuWhitted`]), the
    /// points they end on shaded by the same pass.
    fn shade_exact(&self, caustics: Option<&IrradianceMap>, points: &[ShadePoint]) -> Result<Vec<Vec3>, GpuError> {
        let start = Instant::now();
        let prepared = self.shader.prepare(self.gpu, caustics);
        let mut out = Vec::with_capacity(points.len());
        for part in points.chunks(GpuWhitted::per_dispatch(self.gpu)) {
            let bytes = (part.len() * 16) as u64;
            let part: Vec<ShadeInput> = part.par_iter().map(ShadeInput::new).collect();
            let radiance: Vec<[f32; 4]> = checked(self.gpu, || {
                let radiance = output(self.gpu, "radiance", bytes);
                self.whitted.shade_into(
                    self.gpu,
                    &self.tracer,
                    &self.shader,
                    &prepared,
                    self.light_samples,
                    &part,
                    (&radiance, 0),
                )?;
                read_all(self.gpu, Vec::new(), std::iter::once((&radiance, bytes)))
            })?;
            out.extend(radiance.iter().map(|r| Vec3::new(r[0], r[1], r[2])));
        }
        self.add_times(|t| t.shade_seconds += start.elapsed().as_secs_f64());
        Ok(out)
    }

    /// Upload `scene` and compile the pipeline; pages of up to 4096² texels (less where the adapter
    /// allows less).
    pub fn new(gpu: &'g Gpu, scene: &Scene) -> Result<Self, GpuError> {
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
        let tracer = RayTracer::new(gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)?)?;
        // A power of two, so that Z-order packing of power-of-two squares fills it.
        let side = gpu.device.limits().max_texture_dimension_2d.clamp(32, 4096);
        let page = 1 << (31 - side.leading_zeros());
        Ok(Self {
            gpu,
            bound,
            pipeline,
            gather,
            texels,
            triangles,
            tracer,
            eye: GpuEye::new(gpu, scene)?,
            kept: Mutex::default(),
            shader: PointShader::new(gpu, scene)?,
            composite: GpuComposite::new(gpu)?,
            whitted: GpuWhitted::new(gpu, scene)?,
            light_samples: 64,
            job_pairs: TEXEL_JOB_PAIRS,
            extent: scene.bounds().extent().length(),
            page,
            times: Mutex::default(),
        })
    }

    /// This renderer with `n` shadow rays per area light and shade point (default 64).
    #[must_use]
    pub fn with_light_samples(mut self, n: u32) -> Self {
        self.light_samples = n.max(1);
        self
    }

    /// This renderer splitting a beam's pairs into runs of at most `n` (1 to [`TEXEL_JOB_PAIRS`], the
    /// default) in the compute pass, each run a workgroup's; fewer pairs a run spread a beam over
    /// more workgroups, merged by the atomic max.
    #[must_use]
    pub fn with_job_pairs(mut self, n: u32) -> Self {
        self.job_pairs = n.clamp(1, TEXEL_JOB_PAIRS);
        self
    }

    /// This renderer finding the atlas's nearest hits by rasterization (000's way: a draw per beam,
    /// the depth test keeping the nearest) even where the device could find them by compute.
    #[must_use]
    pub fn rasterized(mut self) -> Self {
        self.texels = None;
        self
    }

    /// Whether this renderer finds the atlas's nearest hits by compute.
    #[must_use]
    pub fn by_compute(&self) -> bool {
        self.texels.is_some()
    }

    /// Whether `gpu` has the 64-bit atomics that finding the atlas's nearest hits by compute takes
    /// (`SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX`, which [`Gpu::new`] asks for).
    #[must_use]
    pub fn can_compute(gpu: &Gpu) -> bool {
        gpu.device.features().contains(wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    }

    /// Time spent so far.
    #[must_use]
    pub fn times(&self) -> GpuTimes {
        *self.times.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    pub(super) fn add_times(&self, f: impl FnOnce(&mut GpuTimes)) {
        f(&mut self.times.lock().unwrap_or_else(std::sync::PoisonError::into_inner));
    }

    /// Render one page of `rows` rows: `beams` with their (beam on the page, scene triangle)
    /// `pairs`, those of beam `i` at `ranges[i]`, the nearest hits by compute where this renderer
    /// can (else by draws). `unpack` reads, where the readback is mapped, the regions' texels (beam
    /// `i`'s from `firsts[i]` on, row by row, [`region_texels`]; `firsts` ends with their total;
    /// each texel as [`Self::unpack`] reads it), and per beam the triangles kept and the texels
    /// tested.
    fn render_page<T>(
        &self,
        beams: &[GpuBeam],
        (pair_buffer, pair_count): (wgpu::Buffer, usize),
        ranges: &[(u32, u32)],
        firsts: &[u32],
        rows: u32,
        unpack: impl FnOnce(&[[u32; 2]], &[Counters]) -> T,
    ) -> Result<T, GpuError> {
        let device = &self.gpu.device;
        let params =
            AtlasParams { size: [self.page as f32, rows as f32], extent: self.extent, pairs: pair_count as u32 };
        let uniform = uniform(self.gpu, "atlas params", bytemuck::bytes_of(&params));
        let beam_buffer = storage(self.gpu, "beams", beams, wgpu::BufferUsages::empty());
        let bounds = output(self.gpu, "bounding triangles", (pair_count * 16) as u64);
        let counters = storage(self.gpu, "counters", &vec![[0u32; 2]; beams.len()], wgpu::BufferUsages::COPY_SRC);
        let texel_count = firsts.last().copied().unwrap_or(0);
        let texel_bytes = u64::from(texel_count) * 8;
        let dense = output(self.gpu, "region texels", texel_bytes);
        let first_texels = storage(self.gpu, "region firsts", firsts, wgpu::BufferUsages::empty());
        let bind = |pipeline: &wgpu::ComputePipeline, entries: &[(u32, &wgpu::Buffer)]| {
            let entries: Vec<_> = entries.iter().map(|&(binding, b)| buffer_entry(binding, b)).collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("atlas"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            })
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("atlas") });
        let group = bind(
            &self.bound,
            &[(0, &uniform), (1, &beam_buffer), (2, &self.triangles), (3, &pair_buffer), (4, &bounds), (6, &counters)],
        );
        let groups = pair_count.div_ceil(WORKGROUP_SIZE as usize).max(1) as u32;
        // The passes' own times on the GPU, where it has timestamp queries.
        let timer = PassTimer::new(self.gpu, if self.by_compute() { 2 } else { 3 });
        compute_pass_timed(&mut encoder, &self.bound, &group, groups, timer.as_ref().map(|t| t.compute(0)));
        match &self.texels {
            Some(texels) => {
                // A job: a workgroup's run of a beam's texels against a run of its pairs.
                let mut jobs: Vec<[u32; 4]> = Vec::new();
                for (k, (&(start, end), w)) in ranges.iter().zip(firsts.windows(2)).enumerate() {
                    for run in 0..(w[1] - w[0]).div_ceil(WORKGROUP_SIZE) {
                        for p in (start..end).step_by(self.job_pairs as usize) {
                            jobs.push([k as u32, run, p, end.min(p + self.job_pairs)]);
                        }
                    }
                }
                let groups = (jobs.len() as u32).max(1);
                let jobs = storage(self.gpu, "texel jobs", &jobs, wgpu::BufferUsages::empty());
                let group = bind(
                    texels,
                    &[
                        (0, &uniform),
                        (1, &beam_buffer),
                        (2, &self.triangles),
                        (3, &pair_buffer),
                        (4, &bounds),
                        (5, &counters),
                        (6, &first_texels),
                        (7, &dense),
                        (8, &jobs),
                    ],
                );
                compute_pass_timed(&mut encoder, texels, &group, groups, timer.as_ref().map(|t| t.compute(1)));
            }
            None => {
                let buffers =
                    PageBuffers { uniform: &uniform, beams: &beam_buffer, pairs: &pair_buffer, bounds: &bounds };
                let outputs = (&counters, &first_texels, &dense);
                self.draw_page(&mut encoder, buffers, outputs, ranges, rows, texel_count, timer.as_ref());
            }
        }
        let count_bytes = beams.len() as u64 * 8;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("atlas readback"),
            size: texel_bytes + count_bytes + timer.as_ref().map_or(0, PassTimer::bytes),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        encoder.copy_buffer_to_buffer(&dense, 0, &readback, 0, texel_bytes);
        encoder.copy_buffer_to_buffer(&counters, 0, &readback, texel_bytes, count_bytes);
        if let Some(timer) = &timer {
            timer.copy_to(&mut encoder, &readback, texel_bytes + count_bytes);
        }
        self.gpu.queue.submit([encoder.finish()]);
        map_with(self.gpu, &readback, |bytes| {
            let (texels, rest) = bytes.split_at(texel_bytes as usize);
            let (counts, stamps) = rest.split_at(count_bytes as usize);
            let passes = PassTimer::seconds(self.gpu, stamps);
            // Compute's nearest hits are the second pass, as the draws are; no gather follows.
            self.add_times(|t| t.atlas_pass_seconds.iter_mut().zip(&passes).for_each(|(a, s)| *a += s));
            // Aligned as mapped ranges are; copied only if a backend mapped them otherwise.
            match (bytemuck::try_cast_slice(texels), bytemuck::try_cast_slice(counts)) {
                (Ok(t), Ok(c)) => unpack(t, c),
                _ => unpack(&bytemuck::pod_collect_to_vec(texels), &bytemuck::pod_collect_to_vec(counts)),
            }
        })
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
        let extent = wgpu::Extent3d { width: self.page, height: rows, depth_or_array_layers: 1 };
        let texture = |format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("atlas"),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let hits = texture(
            wgpu::TextureFormat::Rg32Uint,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let depth = texture(wgpu::TextureFormat::Depth32Float, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let entries: Vec<_> = [
            (0, page.uniform),
            (1, page.beams),
            (2, &self.triangles),
            (3, page.pairs),
            (5, page.bounds),
            (6, counters),
        ]
        .iter()
        .map(|&(binding, b)| buffer_entry(binding, b))
        .collect();
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("atlas"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
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
        let page_view = hits.create_view(&Default::default());
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("atlas gather"),
            layout: &self.gather.get_bind_group_layout(0),
            entries: &[
                buffer_entry(1, page.beams),
                view_entry(7, &page_view),
                buffer_entry(8, firsts),
                buffer_entry(9, dense),
            ],
        });
        let groups = texel_count.div_ceil(WORKGROUP_SIZE).max(1);
        compute_pass_timed(encoder, &self.gather, &group, groups, timer.map(|t| t.compute(2)));
    }
}

/// A page's uniforms, beams, (beam, triangle) pairs and their bounding triangles on the GPU.
#[derive(Clone, Copy)]
struct PageBuffers<'a> {
    uniform: &'a wgpu::Buffer,
    beams: &'a wgpu::Buffer,
    pairs: &'a wgpu::Buffer,
    bounds: &'a wgpu::Buffer,
}

/// Position of the `index`-th square of side `s` in Z order (bits of `index` de-interleaved).
fn z_order(index: u32, s: u32) -> (u32, u32) {
    let (mut x, mut y) = (0, 0);
    for bit in 0..16 {
        x |= ((index >> (2 * bit)) & 1) << bit;
        y |= ((index >> (2 * bit + 1)) & 1) << bit;
    }
    (x * s, y * s)
}

impl BeamRasterizer for GpuBeams<'_> {
    fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, BackendError> {
        let start = Instant::now();
        // Bounding-cone culling on the CPU (000 App. A; the paper culls objects there too), each
        // kept triangle of a coarse face's ring marked PAIR_NEAR (self-hits, as on the CPU); the
        // beams for the shader from the same bounds, placed on their regions below.
        let (candidates, mut gpu_beams): (Vec<Vec<u32>>, Vec<GpuBeam>) = jobs
            .par_iter()
            .map(|j| {
                let tb = j.beam.texel_beam();
                let bounds = tb.s1_or_sn_bounds();
                let mut kept = cone_candidates(scene, tb, &bounds, j.exclude);
                for prim in &mut kept {
                    *prim |= if j.exclude.near(*prim) { PAIR_NEAR } else { 0 };
                }
                (kept, GpuBeam::new(j.beam, &bounds, [0, 0, j.size], j.exclude))
            })
            .unzip();
        // Pack power-of-two squares, largest first, in Z order: every square lands aligned.
        let mut order: Vec<usize> = (0..jobs.len()).collect();
        order.sort_by_key(|&i| std::cmp::Reverse(jobs[i].size.max(1).next_power_of_two()));
        let mut placed: Vec<Option<Placed>> = (0..jobs.len()).map(|_| None).collect();
        let (mut page, mut used) = (0usize, 0u64);
        let capacity = u64::from(self.page) * u64::from(self.page);
        // A page's pairs and their bounding triangles (16 bytes each), its beams and its regions'
        // texels (8 bytes each) must each fit one storage binding.
        let max_pairs = (max_binding(self.gpu) / 16) as usize;
        let max_beams = ((max_binding(self.gpu) / size_of::<GpuBeam>() as u64) as usize).max(1);
        let max_texels = max_binding(self.gpu) / 8;
        let (mut rows, mut pairs, mut beams, mut texels) = (vec![0u32], 0usize, 0usize, 0u64);
        for &i in &order {
            // Each region takes the power-of-two square around it.
            let s = jobs[i].size.max(1).next_power_of_two();
            let t = region_texels(jobs[i].size);
            if s > self.page || t > max_texels {
                return Err(GpuError::BeamTooLarge { size: jobs[i].size, page: self.page }.into());
            }
            let area = u64::from(s) * u64::from(s);
            let n = candidates[i].len();
            if n > max_pairs {
                return Err(GpuError::TooManyTriangles { triangles: n, max: max_pairs }.into());
            }
            if used + area > capacity || pairs + n > max_pairs || beams == max_beams || texels + t > max_texels {
                page += 1;
                (used, pairs, beams, texels) = (0, 0, 0, 0);
                rows.push(0);
            }
            pairs += n;
            beams += 1;
            texels += t;
            let (x, y) = z_order((used / area) as u32, s);
            used += area;
            rows[page] = rows[page].max(y + s);
            placed[i] = Some(Placed { page, x, y });
        }
        let mut textures: Vec<Option<BeamTexture>> = (0..jobs.len()).map(|_| None).collect();
        let by_compute = self.by_compute();
        self.add_times(|t| t.prepare_seconds += start.elapsed().as_secs_f64());
        for (p, &page_rows) in rows.iter().enumerate() {
            let start = Instant::now();
            let members: Vec<usize> =
                order.iter().copied().filter(|&i| placed[i].as_ref().is_some_and(|q| q.page == p)).collect();
            if members.is_empty() {
                continue;
            }
            let mut beams = Vec::with_capacity(members.len());
            let mut ranges = Vec::with_capacity(members.len());
            let mut firsts = Vec::with_capacity(members.len() + 1);
            firsts.push(0u32);
            let mut pair_count = 0u32;
            for (k, &i) in members.iter().enumerate() {
                let q = placed[i].as_ref().ok_or(GpuError::Internal("unplaced beam"))?;
                gpu_beams[i].region[..2].copy_from_slice(&[q.x, q.y]);
                beams.push(gpu_beams[i]);
                // The page's pairs fit one binding, so their count fits 32 bits; so do its texels.
                ranges.push((pair_count, pair_count + candidates[i].len() as u32));
                pair_count += candidates[i].len() as u32;
                firsts.push(firsts[k] + region_texels(jobs[i].size) as u32);
            }
            // The (beam on the page, scene triangle) pairs, written in place, a beam's by a thread.
            let mut pairs =
                Staged::<[u32; 2]>::new(self.gpu, "pairs", pair_count as usize, wgpu::BufferUsages::empty());
            let parts = split_by_counts(pairs.slots(), members.iter().map(|&i| candidates[i].len()))
                .ok_or(GpuError::Internal("pairs past their buffer"))?;
            parts.into_par_iter().zip(&members).enumerate().for_each(|(k, (Slots(out), &i))| {
                out.write_iter(candidates[i].iter().map(|&prim| [k as u32, prim]));
            });
            let pairs = (pairs.finish(self.gpu), pair_count as usize);
            let prepared = start.elapsed().as_secs_f64();
            let unpacking = Cell::new(0.0);
            let unpack = |texels: &[[u32; 2]], counts: &[Counters]| {
                let start = Instant::now();
                let out = Self::unpack(jobs, &members, &firsts, texels, counts, by_compute);
                unpacking.set(start.elapsed().as_secs_f64());
                out
            };
            let unpacked = checked(self.gpu, || self.render_page(&beams, pairs, &ranges, &firsts, page_rows, unpack))??;
            let drawn = start.elapsed().as_secs_f64() - prepared - unpacking.get();
            for (i, tex) in unpacked {
                textures[i] = Some(tex);
            }
            self.add_times(|t| {
                t.atlas_seconds += drawn;
                t.prepare_seconds += prepared + unpacking.get();
                t.pages += 1;
                t.beams += members.len() as u64;
                t.triangles += u64::from(pair_count);
            });
        }
        textures.into_iter().map(|t| t.ok_or_else(|| GpuError::Internal("a beam was not rendered").into())).collect()
    }
}

impl GpuBeams<'_> {
    /// The textures of the beams `members` of one page (`jobs[i]`) from the regions' `texels`,
    /// beam `k`'s row by row from `firsts[k]` on, and per-beam `counts`, as (job index, texture).
    /// A texel is (scene triangle + 1, bits of t), 0 for a miss; `inverted` (by compute,
    /// `beam_texels.wgsl`) each word's bits are inverted, zeroes still a miss.
    fn unpack(
        jobs: &[BeamJob<'_>],
        members: &[usize],
        firsts: &[u32],
        texels: &[[u32; 2]],
        counts: &[Counters],
        inverted: bool,
    ) -> Result<Vec<(usize, BeamTexture)>, GpuError> {
        members
            .par_iter()
            .zip(firsts)
            .zip(counts)
            .map(|((&i, &first), &[kept, tested])| {
                let size = jobs[i].size;
                let region = texels
                    .get(first as usize..first as usize + region_texels(size) as usize)
                    .ok_or(GpuError::Internal("a region's texels were not read back"))?;
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
                let tex = BeamTexture { size, hits, triangles_after_culling: kept, texels_tested: u64::from(tested) };
                Ok((i, tex))
            })
            .collect()
    }
}

impl DeviceWaits for GpuBeams<'_> {
    fn waited_seconds(&self) -> f64 {
        self.gpu.traffic().waited_seconds
    }
}

impl RayQueries for GpuBeams<'_> {
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        let hits = self.trace(rays.par_iter().map(GpuRay::closest).collect())?;
        // The tracer reports the triangle and t; the barycentric weights of the hit point follow.
        Ok(hits
            .into_par_iter()
            .zip(rays)
            .map(|(h, ray)| {
                (h.prim != GpuHit::MISS).then_some(())?;
                let tri = scene.triangles.get(h.prim as usize)?;
                let w = tri.barycentric(ray.at(h.t)).unwrap_or_default();
                Some(Hit { prim: h.prim, t: h.t, u: w.y, v: w.z })
            })
            .collect())
    }

    fn any_hits(&self, _scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        let hits = self.trace(segments.par_iter().map(|(r, t_max)| GpuRay::any(r, *t_max)).collect())?;
        // An any-hit ray's t is 1 when it is occluded, 0 otherwise (`trace_ray`).
        Ok(hits.par_iter().map(|h| h.t == 1.0).collect())
    }
}

impl PointShading for GpuBeams<'_> {
    fn shade_points(
        &self,
        _scene: &Scene,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Result<Option<Vec<Vec3>>, BackendError> {
        // The GPU's shading pass does exact shading (001 eq. 1 by shadow rays) only.
        if options.shading != Shading::Exact {
            return Ok(None);
        }
        self.shade_exact(caustics, points).map(Some).map_err(BackendError::from)
    }

    fn shade_tree(
        &self,
        scene: &Scene,
        smesh: &SMesh,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        levels: &[LevelRadiance],
    ) -> Result<Option<Vec<Vec3>>, BackendError> {
        if options.shading != Shading::Exact || !GpuComposite::fits(self.gpu, levels) {
            return Ok(None);
        }
        let start = Instant::now();
        let kept = self.kept.lock().unwrap_or_else(std::sync::PoisonError::into_inner).take().unwrap_or_default();
        // Mirror and glass points past the tree by Whitted rays in waves, their host time apart.
        // The scene's shading and caustics, uploaded once for the composite and every wave.
        let prepared = self.shader.prepare(self.gpu, caustics);
        let rest = |points: &[ShadeInput], radiance: (&wgpu::Buffer, usize)| {
            let (start, waited) = (Instant::now(), self.gpu.traffic().waited_seconds);
            let out = self.whitted.shade_into(
                self.gpu,
                &self.tracer,
                &self.shader,
                &prepared,
                self.light_samples,
                points,
                radiance,
            );
            let host = start.elapsed().as_secs_f64() - (self.gpu.traffic().waited_seconds - waited);
            self.add_times(|t| t.whitted_host_seconds += host);
            out
        };
        let pixels = checked(self.gpu, || {
            self.composite.run(
                self.gpu,
                &self.tracer,
                &self.shader,
                (scene, smesh),
                &prepared,
                self.light_samples,
                levels,
                &kept,
                &rest,
            )
        });
        self.add_times(|t| {
            t.shade_seconds += start.elapsed().as_secs_f64();
            t.gpu_composites += u64::from(pixels.is_ok());
        });
        pixels.map(Some).map_err(BackendError::from)
    }
}
