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
//! and the gather: a compute GPU rasterizes on few of its cores, a software one on one thread.
//! Rays (the eye's view, the reference's Whitted rays) go to the compute ray tracer; the radiance
//! flows up the tree on the GPU ([`GpuComposite`]): diffuse,
//! glossy and emissive points shaded by [`PointShader`] (area lights by stratified shadow rays,
//! where the CPU's default is exact), specular ones composited from their child beams, only the
//! pixels read back.

use super::beam::GpuBeam;
use super::composite::GpuComposite;
use super::cull::GpuCull;
use super::display::GpuFrame;
use super::eye::{GpuEye, KeptEyeHits, KeptPoints};
use super::fits::{FitTable, ReadFits, fit_slots};
use super::level::{GpuLevelPoints, HostTexel, KeptLevel, LevelKeep};
use super::lookups::{GpuLookups, LookupBeams};
use super::page::Counters;
use super::page_inputs::{PageInputs, PageMemo, page_key};
use super::prepare::{Preparations, Prepared, prepared};
use super::whitted::GpuWhitted;
use crate::buffers::{checked, compute_pipeline, map_all, max_binding, output, shader_module, storage};
use crate::interface::TEXEL_JOB_PAIRS;
use crate::raytrace::RayTracer;
use crate::shade::PointShader;
use crate::{Gpu, GpuError, texels};
use beam_bvh::gpu::{GpuBvh, GpuTriangle};
use beam_render::BackendError;
use beam_render::nonlinear::{
    BeamJob, BeamRasterizer, BeamTexture, CoarseByRays, KeepLevel, KeptTotals, TexelPoint, TexelRadiance, region_texels,
};
use beam_render::options::Shading;
use beam_scene::scene::Scene;
use std::cell::Cell;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

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
    /// Of them, beams whose preparation (bounds, culling by the BVH's boxes) the last frame's tree
    /// had made.
    pub beams_reused: u64,
    /// Of the others, beams whose blocks of the BVH an earlier frame's beam on their face had
    /// gathered, with a cone holding theirs.
    pub blocks_reused: u64,
    /// (beam, scene triangle) pairs on the pages: four per block of the BVH that the host kept
    /// for a beam, those the GPU culled included.
    pub triangles: u64,
    /// Beam trees composited on the GPU (the others fell back to the CPU's composite).
    pub gpu_composites: u64,
    /// Tree levels whose points were kept on the GPU ([`super::GpuLevelPoints`]).
    pub levels_kept: u64,
    /// Lookup jobs of points under coarse S-mesh faces in their child beams made on the GPU
    /// ([`super::GpuLookups`]): reflections and refractions.
    pub lookups: u64,
    /// Texels that tree levels handed to the host and the GPU composited too
    /// ([`super::GpuLevelPoints::records`]).
    pub level_records: u64,
    /// Points under coarse S-mesh faces (the eye's and the levels') whose composite records the
    /// GPU made, each looking its child beams up for its own scattered rays.
    pub coarse_records: u64,
    /// The GPU's own seconds in the atlas passes, by timestamp queries (all 0 where the device has
    /// none): bounding triangles, nearest hits (draws, or the compute pass), gather.
    pub atlas_pass_seconds: [f64; 3],
}

/// The GPU's beam renderer for one scene: its triangles uploaded, the atlas pipeline compiled.
pub struct GpuBeams<'g> {
    pub(super) gpu: &'g Gpu,
    pub(super) bound: wgpu::ComputePipeline,
    pub(super) pipeline: wgpu::RenderPipeline,
    pub(super) gather: wgpu::ComputePipeline,
    /// The nearest hits by compute, where the device has 64-bit atomics (and unless
    /// [`GpuBeams::rasterized`] asked for rasterization).
    pub(super) texels: Option<wgpu::ComputePipeline>,
    pub(super) triangles: wgpu::Buffer,
    /// The per-triangle half of bounding-cone culling.
    pub(super) cull: GpuCull,
    pub(super) tracer: RayTracer,
    /// The eye's view on the GPU.
    pub(super) eye: GpuEye,
    /// The eye's points its last view kept on the GPU, until the composite shades them.
    pub(super) kept: Mutex<Option<Vec<KeptPoints>>>,
    /// The tree levels' points on the GPU.
    pub(super) level: GpuLevelPoints,
    /// The points of the levels it kept, until the composite shades them.
    pub(super) kept_levels: Mutex<Vec<KeptLevel>>,
    /// The mirror and glass hits of the eye's last view kept on the GPU, until the composite makes
    /// their records.
    pub(super) kept_eye_hits: Mutex<Option<KeptEyeHits>>,
    /// The levels of the last frame's tree as the records of points under coarse S-mesh faces
    /// in the level above (the eye's, for the first) look them up, by level (kept on a coarse S
    /// mesh only), until the composite makes them.
    pub(super) child_levels: Mutex<Vec<(usize, LookupBeams)>>,
    /// What the last composite of the eye's hits under coarse faces traced by rays.
    pub(super) coarse_by_rays: Mutex<CoarseByRays>,
    /// Per tree level, the slots its last fit table used and whether it overflowed
    /// ([`fit_slots`]).
    pub(super) fit_slots: Mutex<Vec<Option<(usize, bool)>>>,
    /// Whether it keeps the levels' points and the eye's mirror and glass hits (unless
    /// [`GpuBeams::reading_levels_back`]).
    pub(super) keep_levels: bool,
    /// Whether it leaves each frame on the GPU ([`GpuBeams::displaying`]).
    pub(super) display: bool,
    /// The last frame it left there, until [`GpuBeams::take_frame`].
    pub(super) frame: Mutex<Option<GpuFrame>>,
    /// Shading on the GPU.
    pub(super) shader: PointShader,
    /// The final composite on the GPU.
    pub(super) composite: GpuComposite,
    /// The coarse S mesh's lookups.
    pub(super) lookups: GpuLookups,
    /// The Whitted rays past the tree on the GPU.
    pub(super) whitted: GpuWhitted,
    /// Shadow rays per area light and shade point.
    pub(super) light_samples: u32,
    /// Most pairs a workgroup of the compute pass tests its texels against.
    pub(super) job_pairs: u32,
    pub(super) extent: f32,
    /// Side of an atlas page in texels.
    pub(super) page: u32,
    /// The beams of the last frame's tree and of this one's, made ready for the atlas.
    preparations: Mutex<Preparations>,
    /// The pages of the last frame's tree and of this one's, their inputs uploaded.
    pages: Mutex<PageMemo>,
    times: Mutex<GpuTimes>,
}

/// Where a beam landed: its page and the corner of its region.
struct Placed {
    page: usize,
    x: u32,
    y: u32,
}

impl<'g> GpuBeams<'g> {
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
            cull: GpuCull::new(gpu, scene)?,
            tracer,
            eye: GpuEye::new(gpu, scene)?,
            kept: Mutex::default(),
            level: GpuLevelPoints::new(gpu, scene)?,
            kept_levels: Mutex::default(),
            kept_eye_hits: Mutex::default(),
            child_levels: Mutex::default(),
            coarse_by_rays: Mutex::default(),
            fit_slots: Mutex::default(),
            keep_levels: true,
            display: false,
            frame: Mutex::default(),
            shader: PointShader::new(gpu, scene)?,
            composite: GpuComposite::new(gpu)?,
            lookups: GpuLookups::new(gpu)?,
            whitted: GpuWhitted::new(gpu, scene)?,
            light_samples: 64,
            job_pairs: TEXEL_JOB_PAIRS,
            extent: scene.bounds().extent().length(),
            page,
            preparations: Mutex::default(),
            pages: Mutex::default(),
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

    /// This renderer reading every tree level's hits and the eye's mirror and glass hits back for
    /// the host instead of keeping on the GPU what needs no host ([`super::GpuLevelPoints`],
    /// [`GpuEye`]): the way every level went before, which the tests compare with.
    #[must_use]
    pub fn reading_levels_back(mut self) -> Self {
        self.keep_levels = false;
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
        *self.times.lock().unwrap_or_else(PoisonError::into_inner)
    }

    pub(super) fn add_times(&self, f: impl FnOnce(&mut GpuTimes)) {
        f(&mut self.times.lock().unwrap_or_else(PoisonError::into_inner));
    }
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
        Ok(self.render(scene, jobs, None, false)?.0)
    }

    /// Kept where the composite will shade the tree (exact shading, the level within one texture),
    /// unless [`GpuBeams::reading_levels_back`] asked otherwise.
    fn render_level(
        &self,
        scene: &Scene,
        jobs: &[BeamJob<'_>],
        keep: &KeepLevel<'_>,
    ) -> Result<(Vec<BeamTexture>, Option<KeptTotals>), BackendError> {
        if keep.level <= 1 {
            self.preparations.lock().unwrap_or_else(PoisonError::into_inner).next_frame();
            self.pages.lock().unwrap_or_else(PoisonError::into_inner).next_frame();
        }
        let shaded_here = keep.options.shading == Shading::Exact && texels::fits(self.gpu, keep.layout.len);
        if !self.keep_levels || !shaded_here {
            return Ok((self.render(scene, jobs, None, true)?.0, None));
        }
        let (textures, kept) = self.render(scene, jobs, Some(keep), true)?;
        let mut kept = kept.ok_or(GpuError::Internal("a level to keep was not kept"))?;
        // On a coarse S mesh the records of the level above (the eye's, for the first) look their
        // points up in this one: in the depths written on the GPU, else in every hit read back.
        let mut child_levels = self.child_levels.lock().unwrap_or_else(PoisonError::into_inner);
        child_levels.retain(|(l, _)| *l < keep.level);
        if let Some(depths) = kept.depths.take() {
            let regions = keep.layout.firsts.iter().zip(jobs).map(|(&first, j)| (j.beam, [first, 0, j.size]));
            child_levels.push((keep.level, LookupBeams::on_regions(self.gpu, regions, depths)));
        } else if keep.with_hits {
            let beams: Vec<_> = jobs.iter().map(|j| j.beam).zip(&textures).collect();
            if let Some(level) = checked(self.gpu, || LookupBeams::upload(self.gpu, &beams))? {
                child_levels.push((keep.level, level));
            }
        }
        drop(child_levels);
        let records = self.composites_handed_back(keep);
        // Texels whose fits the GPU summed are kept there too.
        let summed: u64 = if kept.fits { kept.host.iter().map(|(_, n)| u64::from(*n)).sum() } else { 0 };
        let totals = KeptTotals { points: kept.points() + summed, curved: kept.curved, records, fits: kept.fits };
        self.add_times(|t| t.levels_kept += 1);
        let mut levels = self.kept_levels.lock().unwrap_or_else(PoisonError::into_inner);
        // A frame's first level: what an earlier frame left (one that failed) goes.
        levels.retain(|l| l.level < keep.level);
        levels.push(kept);
        Ok((textures, Some(totals)))
    }

    fn kept_level_points(&self, level: usize) -> Result<Vec<Vec<TexelPoint>>, BackendError> {
        let levels = self.kept_levels.lock().unwrap_or_else(PoisonError::into_inner);
        let Some(kept) = levels.iter().find(|l| l.level == level && l.fits) else {
            return Ok(Vec::new());
        };
        Ok(checked(self.gpu, || kept.host_points(self.gpu))?)
    }

    fn take_kept_levels(&self) -> Result<Vec<(usize, Vec<TexelRadiance>)>, BackendError> {
        let levels = std::mem::take(&mut *self.kept_levels.lock().unwrap_or_else(PoisonError::into_inner));
        let read = |l: &KeptLevel| Ok((l.level, l.read_back(self.gpu)?));
        Ok(checked(self.gpu, || levels.iter().map(read).collect())?)
    }
}

impl GpuBeams<'_> {
    /// Into `textures` (level `level`'s, kept as `kept`), the fits summed in `table`; where it
    /// overflowed, the texels it was given instead, read back (and a larger table next frame).
    fn read_fits(
        &self,
        table: &FitTable,
        kept: &mut KeptLevel,
        textures: &mut [BeamTexture],
        level: usize,
    ) -> Result<(), GpuError> {
        let start = Instant::now();
        let read = checked(self.gpu, || table.read(self.gpu))?;
        let last = match read {
            Some(ReadFits { fits, used }) => {
                for (tex, fits) in textures.iter_mut().zip(fits) {
                    tex.fits = fits;
                }
                kept.fits = true;
                (used, false)
            }
            None => {
                for (tex, points) in textures.iter_mut().zip(checked(self.gpu, || kept.host_points(self.gpu))?) {
                    tex.points = points;
                }
                (table.params().0 as usize, true)
            }
        };
        let mut slots = self.fit_slots.lock().unwrap_or_else(PoisonError::into_inner);
        if slots.len() <= level {
            slots.resize(level + 1, None);
        }
        slots[level] = Some(last);
        self.add_times(|t| t.atlas_seconds += start.elapsed().as_secs_f64());
        Ok(())
    }

    /// Whether the composite makes the records of the texels a level kept as `keep` hands back:
    /// on an S mesh whose faces fit one binding (as the eye's records).
    fn composites_handed_back(&self, keep: &KeepLevel<'_>) -> bool {
        GpuComposite::faces_fit(self.gpu, keep.faces)
    }

    /// The textures of `jobs`; with `keep`, the points of the texels from which the tree does not go
    /// on kept on the GPU ([`super::GpuLevelPoints`]), the textures holding only the others' hits
    /// (every hit `keep.with_hits`); with `reuse`, beams of a frame's tree, each prepared once for
    /// this frame and the next ([`Preparations`]).
    fn render(
        &self,
        scene: &Scene,
        jobs: &[BeamJob<'_>],
        keep: Option<&KeepLevel<'_>>,
        reuse: bool,
    ) -> Result<(Vec<BeamTexture>, Option<KeptLevel>), BackendError> {
        let start = Instant::now();
        // Bounding-cone culling (000 App. A) by the BVH's boxes here, triangle by triangle on the
        // GPU (`super::cull`); the beams for the shader from the same bounds, placed on their
        // regions below.
        let mut memo = reuse.then(|| self.preparations.lock().unwrap_or_else(PoisonError::into_inner));
        let before = memo.as_ref().map_or((0, 0), |m| m.reused());
        let culled = prepared(scene, jobs, memo.as_deref_mut());
        let after = memo.map_or((0, 0), |m| m.reused());
        self.add_times(|t| {
            t.beams_reused += after.0 - before.0;
            t.blocks_reused += after.1 - before.1;
        });
        // Four (beam, triangle) pairs per block, some of them culled on the GPU.
        let pairs_of = |i: usize| 4 * culled[i].blocks.len();
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
            let n = pairs_of(i);
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
        let mut kept = keep.map(|k| KeptLevel::new(k.level, k.layout));
        let kinds = keep.map(|k| self.level.kinds(self.gpu, k.continues));
        let by_compute = self.by_compute();
        let composited_here = keep.is_some_and(|k| self.composites_handed_back(k));
        // Under a coarse S mesh, the level's depths for the lookups of the level above, written
        // where they lie (then no hit but the host's is read back), where they fit one binding
        // and the GPU composites the level above (its points located by the eye's candidates).
        let eye = self.kept_eye_hits.lock().unwrap_or_else(PoisonError::into_inner);
        let locate = eye.as_ref().map(|e| &e.locate);
        let depths = keep.filter(|k| {
            let fits = k.layout.len as u64 * 4 <= max_binding(self.gpu);
            k.with_hits && fits && composited_here && locate.is_some()
        });
        let depths = depths.map(|k| output(self.gpu, "level depths", k.layout.len.max(1) as u64 * 4));
        // The texels the tree goes on from, where the GPU composites them: their fits summed on
        // the GPU, and none read back, where their faces are located there.
        let fit_table = keep.filter(|k| {
            let read_back = k.with_hits && depths.is_none();
            composited_here && !read_back && locate.is_some() && !k.continues.is_empty()
        });
        let fit_table = fit_table.and_then(|k| {
            let last = self.fit_slots.lock().unwrap_or_else(PoisonError::into_inner).get(k.level).copied().flatten();
            FitTable::new(self.gpu, fit_slots(last, jobs.len()), jobs.len(), k.faces, max_binding(self.gpu))
        });
        let locate = self.eye.locate_or_none(locate);
        self.add_times(|t| t.prepare_seconds += start.elapsed().as_secs_f64());
        for (p, &page_rows) in rows.iter().enumerate() {
            let start = Instant::now();
            let members: Vec<usize> =
                order.iter().copied().filter(|&i| placed[i].as_ref().is_some_and(|q| q.page == p)).collect();
            if members.is_empty() {
                continue;
            }
            let regions = members
                .iter()
                .map(|&i| placed[i].as_ref().map(|q| [q.x, q.y, jobs[i].size]))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| GpuError::Internal("unplaced beam"))?;
            let preps: Vec<&Arc<Prepared>> = members.iter().map(|&i| &culled[i]).collect();
            // The page's inputs: those of the last frame's page with the same beams on the same
            // regions, else uploaded.
            let upload = || {
                let job_pairs = by_compute.then_some(self.job_pairs);
                Arc::new(PageInputs::new(self.gpu, jobs, &members, (&preps, &regions), job_pairs))
            };
            let found = reuse.then(|| {
                let mut pages = self.pages.lock().unwrap_or_else(PoisonError::into_inner);
                pages.values(vec![page_key(&preps, &regions)], |_| upload()).pop()
            });
            let inputs = found.flatten().unwrap_or_else(upload);
            let pair_count = inputs.pairs as u32;
            let firsts = &inputs.firsts;
            let prepared = start.elapsed().as_secs_f64();
            let unpacking = Cell::new(0.0);
            let with_hits = keep.is_none_or(|k| k.with_hits) && depths.is_none();
            let unpack = |texels: &[[u32; 2]], counts: &[Counters]| {
                let start = Instant::now();
                let texels = with_hits.then_some(texels);
                let out = Self::unpack(jobs, &members, firsts, texels, counts, by_compute);
                unpacking.set(start.elapsed().as_secs_f64());
                out
            };
            // Per beam where the level is kept: its first texel in the level, its face's triangle,
            // its index in the level.
            let placed: Vec<[u32; 4]> = match keep {
                Some(k) => members.iter().map(|&i| [k.layout.firsts[i], k.layout.prims[i], i as u32, 0]).collect(),
                None => Vec::new(),
            };
            let keep_page = kinds.as_ref().map(|kinds| LevelKeep {
                placed: &placed,
                kinds,
                with_hits,
                locate,
                depths: depths.as_ref(),
                fits: fit_table.as_ref(),
            });
            let (unpacked, appended) =
                checked(self.gpu, || self.render_page(&inputs, page_rows, keep_page.as_ref(), unpack))?;
            let mut unpacked = unpacked?;
            if let (Some(kept), Some((appended, counts))) = (kept.as_mut(), appended) {
                if !with_hits && fit_table.is_none() {
                    // The texels the host builds on, with their points, into textures otherwise empty.
                    // Unpacked from where they are mapped (12.9 MB a frame on the glass lens).
                    let start = Instant::now();
                    let size = size_of::<HostTexel>() as u64;
                    let sources = appended.iter().zip(&counts).map(|(a, c)| (&*a.host, u64::from(c.host) * size));
                    let unpack = |bytes: &[u8]| {
                        let start = Instant::now();
                        let out = Self::unpack_host_texels(&mut unpacked, bytes);
                        (out, start.elapsed().as_secs_f64())
                    };
                    let (out, unpacking) = checked(self.gpu, || map_all(self.gpu, Vec::new(), sources, unpack))?;
                    out?;
                    self.add_times(|t| {
                        t.atlas_seconds += start.elapsed().as_secs_f64() - unpacking;
                        t.prepare_seconds += unpacking;
                    });
                }
                kept.add(appended, &counts, composited_here);
            }
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
        let textures = textures.into_iter().map(|t| t.ok_or_else(|| GpuError::Internal("a beam was not rendered")));
        let mut textures: Vec<BeamTexture> = textures.collect::<Result<_, _>>()?;
        if let (Some(kept), Some(depths)) = (kept.as_mut(), depths) {
            kept.depths = Some(depths);
        }
        if let (Some(kept), Some(table), Some(k)) = (kept.as_mut(), fit_table, keep) {
            self.read_fits(&table, kept, &mut textures, k.level)?;
        }
        Ok((textures, kept))
    }
}
