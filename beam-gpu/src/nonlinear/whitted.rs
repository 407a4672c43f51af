//! Whitted rays past the beam tree on the GPU (`shaders/whitted.wgsl`): mirror and glass points
//! send on their specular rays, traced for at most [`MAX_DEPTH`] bounces without leaving the GPU;
//! the points the paths end on are shaded there by [`PointShader`] and their radiance, times each
//! path's weight, added to the point it started from. Each point's paths are followed depth first
//! in one dispatch (`whitted_paths.rs`), or, where their ends would not fit one shading, in waves
//! (a dispatch per bounce). The host reads back three counts per dispatch, nothing else; the ends
//! are shaded together after the last dispatch (one shading and its wait), and so are the paths
//! and ends of every batch of points given in one call ([`RestJob`]). CPU twin:
//! [`shade_by_waves`] with [`specular_rays`].
//!
//! [`shade_by_waves`]: beam_render::nonlinear::shade_by_waves
//! [`specular_rays`]: beam_render::specular::specular_rays

use crate::buffers::{
    buffer_entry, compute_pipeline, encode_pass, max_binding, output, read_all, storage, uniform, view_entry,
};
use crate::checks::ShadeChecks;
use crate::interface::{NONE, SPECULAR_GLASS, SPECULAR_MIRROR, SPECULAR_THIN};
use crate::raytrace::RayTracer;
use crate::scratch::{Scratch, scratch};
use crate::shade::{PointShader, ShadeInput, ShadeScene, Shaded};
use crate::texels;
use crate::{Gpu, GpuError};
use beam_math::glam::Vec3;
use beam_render::specular::MAX_DEPTH;
use beam_render::tolerance::shading_eps;
use beam_scene::scene::{Bump, Material, Scene};
use bytemuck::{Pod, Zeroable};
use std::sync::atomic::AtomicU64;

/// Uniforms of one dispatch.
///
/// WGSL twin: `WhittedParams` in `shaders/whitted.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct WhittedParams {
    /// Items of the dispatch.
    pub count: u32,
    /// `wave`: its first path in the input; `start`: the destination of its first point;
    /// `gather`: its first end.
    pub first: u32,
    /// 1 on the last wave (specular hits end there, unshaded).
    pub last: u32,
    /// Offset of the specular rays' origins off the surface.
    pub eps: f32,
}

/// A mirror or glass triangle: what [`specular_rays`](beam_render::specular::specular_rays) reads.
///
/// WGSL twin: `SpecularPrim` in `shaders/whitted.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SpecularPrim {
    /// First vertex.
    pub v0: [f32; 3],
    /// [`SPECULAR_MIRROR`], [`SPECULAR_GLASS`] or [`SPECULAR_THIN`].
    pub kind: u32,
    /// Second vertex.
    pub v1: [f32; 3],
    /// A glass's index of refraction.
    pub ior: f32,
    /// Third vertex.
    pub v2: [f32; 3],
    /// 1 where `n0`–`n2` are smooth vertex normals, 0 for none.
    pub has_normals: u32,
    /// Smooth normal of the first vertex.
    pub n0: [f32; 3],
    /// A mirror's bump map: its largest tilt δ (0 for none).
    pub delta: f32,
    /// Smooth normal of the second vertex.
    pub n1: [f32; 3],
    /// The bump map's wavelength.
    pub wavelength: f32,
    /// Smooth normal of the third vertex.
    pub n2: [f32; 3],
    /// Padding.
    pub pad0: u32,
    /// Unit geometric normal ([`Scene::normal`]).
    pub normal: [f32; 3],
    /// Padding.
    pub pad1: u32,
    /// A mirror's or thin pane's tint.
    pub tint: [f32; 3],
    /// Padding.
    pub pad2: u32,
}

/// `Rgba32Uint` texels of one [`SpecularPrim`].
const TEXELS_PER_PRIM: usize = size_of::<SpecularPrim>() / 16;

/// A path: its next ray, the radiance it adds to and with what weight.
///
/// WGSL twin: `Path` in `shaders/whitted.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct WhittedPath {
    /// Origin of its next ray.
    pub origin: [f32; 3],
    /// Index of the radiance it adds to.
    pub dest: u32,
    /// Direction of its next ray.
    pub direction: [f32; 3],
    /// Shading seed of its ends (the 32-bit seed of the point it started from).
    pub seed: u32,
    /// Its weight.
    pub weight: [f32; 3],
    /// Padding.
    pub pad: u32,
}

/// Of a path's end (a shading input): its weight and the radiance it adds to.
///
/// WGSL twin: `EndWeight` in `shaders/whitted.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct EndWeight {
    /// The path's weight.
    pub weight: [f32; 3],
    /// Index of the radiance it adds to.
    pub dest: u32,
}

/// What one dispatch appended.
///
/// WGSL twin: `WhittedCounts` in `shaders/whitted.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct WhittedCounts {
    /// Paths appended.
    pub paths: u32,
    /// Ends appended.
    pub ends: u32,
    /// 1 + the largest item whose traversal overflowed its stack, 0 for none.
    pub overflow: u32,
    /// Padding.
    pub pad: u32,
}

const _: () = assert!(
    size_of::<WhittedParams>() == 16
        && size_of::<SpecularPrim>() == 128
        && size_of::<WhittedPath>() == 48
        && size_of::<EndWeight>() == 16
        && size_of::<WhittedCounts>() == 16
);

/// The points [`GpuWhitted::shade_into`] shades: a batch on the host, or the first `count`
/// [`ShadeInput`]s of a buffer already on the GPU (at most [`GpuWhitted::per_dispatch`]).
#[derive(Clone, Copy)]
pub enum RestPoints<'a> {
    /// On the host.
    Host(&'a [ShadeInput]),
    /// On the GPU: a buffer and how many of its points.
    Gpu(&'a wgpu::Buffer, usize),
}

/// A batch of points for [`GpuWhitted::shade_into`] and where their radiance goes: point `i`'s
/// is added to element `first + i` of `radiance` (a buffer of `vec4<f32>`s).
#[derive(Clone, Copy)]
pub struct RestJob<'a> {
    /// The points.
    pub points: RestPoints<'a>,
    /// The buffer their radiance is added to.
    pub radiance: &'a wgpu::Buffer,
    /// The element of the first point's.
    pub first: usize,
}

/// The Whitted waves for one scene: its mirror and glass triangles uploaded, for the renderer's
/// life (with one estimate each composite leaves for the next, `ends_per_point`).
pub struct GpuWhitted {
    start: wgpu::ComputePipeline,
    wave: wgpu::ComputePipeline,
    /// Each point's paths followed depth first in one dispatch ([`Self::depth_first`]).
    pub(super) paths: wgpu::ComputePipeline,
    gather: wgpu::ComputePipeline,
    /// Per scene triangle: its index in `specular`, or [`NONE`].
    slots: wgpu::Buffer,
    /// The [`SpecularPrim`]s, eight `Rgba32Uint` texels each ([`crate::texels`]).
    specular: wgpu::TextureView,
    eps: f32,
    /// Whether the paths are followed depth first (else in waves only).
    depth_first: bool,
    /// The most ends per point the last depth-first dispatches appended: the room the next ones
    /// start with (across frames: an estimate each composite leaves for the next; the bits of an
    /// `f64`, read and written whole, no lock).
    pub(super) ends_per_point: AtomicU64,
}

/// A dispatch's ends: their shading inputs, their paths' weights and destinations, how many.
pub(super) struct Ends {
    pub(super) inputs: Scratch,
    pub(super) weights: Scratch,
    pub(super) count: u32,
}

/// One dispatch's output: paths, ends, counts.
pub(super) struct Appended {
    paths: Scratch,
    pub(super) ends: Scratch,
    pub(super) weights: Scratch,
    pub(super) counts: wgpu::Buffer,
}

/// A batch of Whitted ends shaded ([`GpuWhitted::shade_ends`]): the shading, and the ends and
/// their weights copied into one buffer each where the batch joined several, held until the
/// encoder they were added to is submitted.
type ShadedEnds = (Shaded, Option<(Scratch, Scratch)>);

impl GpuWhitted {
    /// The scene's mirror and glass triangles: per scene triangle its slot ([`NONE`] for none),
    /// and the [`SpecularPrim`]s in their texture (what `lib/specular.wgsl` reads).
    pub(super) fn specular_prims(&self) -> (&wgpu::Buffer, &wgpu::TextureView) {
        (&self.slots, &self.specular)
    }

    /// Compile the passes and upload `scene`'s mirror and glass triangles.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let mut slots = vec![NONE; scene.triangles.len()];
        let mut specular = Vec::new();
        for (i, slot) in slots.iter_mut().enumerate() {
            let (kind, tint, ior, bump) = match scene.material(i as u32) {
                Material::Mirror { tint, bump } => (SPECULAR_MIRROR, tint, 0.0, bump),
                Material::Glass { ior } => (SPECULAR_GLASS, Vec3::ONE, ior, Bump::NONE),
                Material::ThinGlass { tint, .. } => (SPECULAR_THIN, tint, 0.0, Bump::NONE),
                _ => continue,
            };
            let t = &scene.triangles[i];
            let n = scene.smooth_normals.get(&(i as u32));
            let vn = |k: usize| n.map_or([0.0; 3], |n| n[k].to_array());
            *slot = specular.len() as u32;
            specular.push(SpecularPrim {
                v0: t.v[0].to_array(),
                kind,
                v1: t.v[1].to_array(),
                ior,
                v2: t.v[2].to_array(),
                has_normals: u32::from(n.is_some()),
                n0: vn(0),
                delta: bump.delta,
                n1: vn(1),
                wavelength: bump.wavelength,
                n2: vn(2),
                pad0: 0,
                normal: scene.normal(i as u32).to_array(),
                pad1: 0,
                tint: tint.to_array(),
                pad2: 0,
            });
        }
        if !texels::fits(gpu, TEXELS_PER_PRIM * specular.len()) {
            let max = texels::width(gpu) as usize * gpu.device.limits().max_texture_dimension_2d as usize;
            return Err(GpuError::TooManySpecular { triangles: specular.len(), max: max / TEXELS_PER_PRIM });
        }
        Ok(Self {
            start: compute_pipeline(gpu, "whitted", "start")?,
            wave: compute_pipeline(gpu, "whitted", "wave")?,
            paths: compute_pipeline(gpu, "whitted", "paths")?,
            gather: compute_pipeline(gpu, "whitted", "gather")?,
            slots: storage(gpu, "specular slots", &slots, wgpu::BufferUsages::empty()),
            specular: texels::upload(
                gpu,
                "specular triangles",
                bytemuck::cast_slice::<SpecularPrim, [u32; 4]>(&specular),
                wgpu::TextureFormat::Rgba32Uint,
            )
            .create_view(&Default::default()),
            eps: shading_eps(scene),
            depth_first: true,
            ends_per_point: AtomicU64::new(1.0f64.to_bits()),
        })
    }

    /// Items one dispatch takes: its output paths (two per item) within one storage binding, its
    /// ends within what [`PointShader::shade_inputs`] takes.
    #[must_use]
    pub fn per_dispatch(gpu: &Gpu) -> usize {
        let by_paths = (max_binding(gpu) / (2 * size_of::<WhittedPath>()) as u64) as usize;
        by_paths.min(PointShader::max_points(gpu)).clamp(1, 1 << 20)
    }

    /// Adds the radiance of each job's points to its buffer ([`RestJob`]): as the CPU's
    /// `shade_by_waves` computes it, diffuse, glossy and emissive points (and the ends of the
    /// others' specular paths) shaded by `shader` (`spp` shadow rays per area light, the scene
    /// `prepared`). Each point's paths are followed depth first in one dispatch, every job's
    /// dispatches submitted and waited for together (`whitted_paths.rs`); where their ends
    /// would not fit one shading, in waves (each one submission and one wait for its counts).
    /// Their ends go in as few shadings as hold them, each given `checks`
    /// ([`PointShader::shade_inputs`]). Call inside [`crate::buffers::checked`].
    pub fn shade_into(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        (shader, prepared, spp): (&PointShader, &ShadeScene, u32),
        jobs: &[RestJob<'_>],
        mut checks: Option<&mut ShadeChecks>,
    ) -> Result<(), GpuError> {
        let depth_first = if self.depth_first { self.depth_first(gpu, tracer, jobs)? } else { None };
        let mut ends = match depth_first {
            Some(ends) => ends,
            None => self.waves(gpu, tracer, jobs)?,
        };
        // By job, as many ends a shading as one takes, the shadings in one submission (unless
        // they wait for the device).
        let chunk = Self::per_dispatch(gpu);
        ends.sort_by_key(|(_, j)| *j);
        let (mut batches, mut points): (Vec<Vec<(Ends, usize)>>, usize) = (Vec::new(), 0);
        for e in ends {
            let n = e.0.count as usize;
            match batches.last_mut() {
                Some(batch) if points + n <= chunk => batch.push(e),
                _ => {
                    batches.push(vec![e]);
                    points = 0;
                }
            }
            points += n;
        }
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let shading = (tracer, shader, prepared, spp);
        let held = batches
            .iter()
            .map(|batch| self.shade_ends(gpu, shading, batch, jobs, checks.as_deref_mut(), &mut encoder))
            .collect::<Result<Vec<_>, GpuError>>()?;
        gpu.submit([encoder.finish()]);
        drop(held);
        Ok(())
    }

    /// This renderer following Whitted paths in waves only (a dispatch per bounce), as the tests
    /// compare with.
    #[must_use]
    pub fn in_waves(mut self) -> Self {
        self.depth_first = false;
        self
    }

    /// The ends of the paths of `jobs`' points, each with its job, traced in waves: every job's
    /// paths go in the same waves, each one submission and one wait for its counts.
    fn waves(&self, gpu: &Gpu, tracer: &RayTracer, jobs: &[RestJob<'_>]) -> Result<Vec<(Ends, usize)>, GpuError> {
        let chunk = Self::per_dispatch(gpu);
        let mut dispatched = Vec::new();
        for (j, job) in jobs.iter().enumerate() {
            match job.points {
                RestPoints::Host(points) => {
                    for (k, part) in points.chunks(chunk).enumerate() {
                        let inputs = storage(gpu, "whitted points", part, wgpu::BufferUsages::empty());
                        let items = (part.len(), job.first + k * chunk, false);
                        let inputs = [buffer_entry(5, &inputs)];
                        dispatched.push((self.dispatch(gpu, &self.start, items, &inputs, None), j));
                    }
                }
                RestPoints::Gpu(inputs, count) => {
                    if count > chunk {
                        return Err(GpuError::Internal("more points on the GPU than one Whitted dispatch takes"));
                    }
                    let items = (count, job.first, false);
                    let inputs = [buffer_entry(5, inputs)];
                    dispatched.push((self.dispatch(gpu, &self.start, items, &inputs, None), j));
                }
            }
        }
        // The paths' ends of every wave, shaded together once the waves are done.
        let mut ends = Vec::new();
        let mut batches = self.finish(gpu, dispatched, &mut ends)?;
        for depth in 1..=MAX_DEPTH {
            if batches.is_empty() {
                break;
            }
            let (nodes, triangles) = tracer.buffers();
            let mut dispatched = Vec::new();
            for (paths, count, j) in &batches {
                let entries = [buffer_entry(0, nodes), buffer_entry(1, triangles), buffer_entry(6, paths)];
                for from in (0..*count as usize).step_by(chunk) {
                    let n = chunk.min(*count as usize - from);
                    let items = (n, from, depth == MAX_DEPTH);
                    dispatched.push((self.dispatch(gpu, &self.wave, items, &entries, None), *j));
                }
            }
            batches = self.finish(gpu, dispatched, &mut ends)?;
        }
        Ok(ends)
    }

    /// One dispatch of `pipeline` over `count` items from `from`, its outputs made (room for
    /// `paths` paths and `ends` ends; by default two paths and one end an item), its `inputs`
    /// bound; an encoder holding it.
    pub(super) fn dispatch(
        &self,
        gpu: &Gpu,
        pipeline: &wgpu::ComputePipeline,
        (count, from, last): (usize, usize, bool),
        inputs: &[wgpu::BindGroupEntry<'_>],
        rooms: Option<(usize, usize)>,
    ) -> (wgpu::CommandEncoder, Appended) {
        let params = WhittedParams { count: count as u32, first: from as u32, last: u32::from(last), eps: self.eps };
        let params = uniform(gpu, "whitted params", bytemuck::bytes_of(&params));
        let bytes = |each: usize, n: usize| (each * n.max(1)) as u64;
        let (paths, ends) = rooms.unwrap_or((2 * count, count));
        // Counts zeroed by wgpu.
        let out = Appended {
            paths: scratch(gpu, "whitted paths", bytes(size_of::<WhittedPath>(), paths)),
            ends: scratch(gpu, "whitted ends", bytes(size_of::<ShadeInput>(), ends)),
            weights: scratch(gpu, "whitted end weights", bytes(size_of::<EndWeight>(), ends)),
            counts: output(gpu, "whitted counts", size_of::<WhittedCounts>() as u64),
        };
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let mut entries = vec![
            buffer_entry(2, &params),
            buffer_entry(3, &self.slots),
            view_entry(4, &self.specular),
            buffer_entry(7, &out.paths),
            buffer_entry(8, &out.ends),
            buffer_entry(9, &out.weights),
            buffer_entry(10, &out.counts),
        ];
        entries.extend_from_slice(inputs);
        encode_pass(gpu, &mut encoder, pipeline, count as u32, &entries);
        (encoder, out)
    }

    /// Submit `dispatched` (each with its job) and read their counts back; their ends go to
    /// `ends`, the paths they appended are returned, each buffer with its count and job.
    fn finish(
        &self,
        gpu: &Gpu,
        dispatched: Vec<((wgpu::CommandEncoder, Appended), usize)>,
        ends: &mut Vec<(Ends, usize)>,
    ) -> Result<Vec<(Scratch, u32, usize)>, GpuError> {
        let (encoders, outs): (Vec<_>, Vec<_>) = dispatched.into_iter().map(|((e, o), j)| (e.finish(), (o, j))).unzip();
        // One submission with the counts' copy (a second would wait for the first, uncounted).
        let counts = outs.iter().map(|(o, _)| (&o.counts, size_of::<WhittedCounts>() as u64));
        let counts: Vec<WhittedCounts> = read_all(gpu, encoders, counts)?;
        if let Some(c) = counts.iter().find(|c| c.overflow > 0) {
            return Err(GpuError::StackOverflow { ray: c.overflow as usize - 1 });
        }
        let mut next = Vec::new();
        for ((out, j), c) in outs.into_iter().zip(counts) {
            if c.ends > 0 {
                ends.push((Ends { inputs: out.ends, weights: out.weights, count: c.ends }, j));
            }
            if c.paths > 0 {
                next.push((out.paths, c.paths, j));
            }
        }
        Ok(next)
    }

    /// Add to `encoder` the shading of the ends of `batch` (at most [`Self::per_dispatch`] in all,
    /// each with its job, a job's together) and the passes that add each, times its path's weight,
    /// to its point's element of its job's radiance. Several waves' ends are first copied into one
    /// buffer. Returns what to hold until `encoder` is submitted: the shading and the copies.
    fn shade_ends(
        &self,
        gpu: &Gpu,
        (tracer, shader, prepared, spp): (&RayTracer, &PointShader, &ShadeScene, u32),
        batch: &[(Ends, usize)],
        jobs: &[RestJob<'_>],
        checks: Option<&mut ShadeChecks>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Option<ShadedEnds>, GpuError> {
        let count: u32 = batch.iter().map(|(e, _)| e.count).sum();
        let mut joined = None;
        let (inputs, weights) = match batch {
            [] => return Ok(None),
            [(one, _)] => (&one.inputs, &one.weights),
            _ => {
                let size = |each: usize| (each * count as usize) as u64;
                let joined = joined.insert((
                    scratch(gpu, "whitted ends", size(size_of::<ShadeInput>())),
                    scratch(gpu, "whitted end weights", size(size_of::<EndWeight>())),
                ));
                let mut at = 0;
                for (e, _) in batch {
                    let n = u64::from(e.count);
                    let (i, w) = (size_of::<ShadeInput>() as u64, size_of::<EndWeight>() as u64);
                    encoder.copy_buffer_to_buffer(&e.inputs, 0, &joined.0, at * i, n * i);
                    encoder.copy_buffer_to_buffer(&e.weights, 0, &joined.1, at * w, n * w);
                    at += n;
                }
                (&joined.0, &joined.1)
            }
        };
        let shaded = shader.shade_inputs(gpu, tracer, prepared, spp, (inputs, count as usize, 0), checks, encoder)?;
        // A gather per job: its ends lie together.
        let mut first = 0;
        for run in batch.chunk_by(|a, b| a.1 == b.1) {
            let n: u32 = run.iter().map(|(e, _)| e.count).sum();
            let radiance = jobs.get(run[0].1).ok_or(GpuError::Internal("a Whitted end without its job"))?.radiance;
            let params = WhittedParams { count: n, first, last: 0, eps: self.eps };
            let params = uniform(gpu, "whitted params", bytemuck::bytes_of(&params));
            let entries = [
                buffer_entry(2, &params),
                buffer_entry(9, weights),
                buffer_entry(11, &shaded.radiance),
                buffer_entry(12, radiance),
            ];
            encode_pass(gpu, encoder, &self.gather, n, &entries);
            first += n;
        }
        Ok(Some((shaded, joined)))
    }
}
