//! The tree levels' stage of the nonlinear pipeline of 000 §3 ([`GpuAtlas`],
//! `shaders/beam_atlas.wgsl`): every beam of a tree level packed into square regions of atlas
//! pages, one draw per beam (the instance) over the scene triangles its bounding cone keeps
//! (pulled from a storage buffer by vertex index / 3); the vertex stage emits each triangle's
//! bounding triangle on the beam's region, the fragment stage intersects the texel's ray with it,
//! and the depth test keeps the nearest hit. A page takes no more beams, and no more (beam,
//! triangle) pairs or region texels, than one storage binding of the device holds. A compute pass
//! gathers each page's regions into one list (a triangular region fills under half of its
//! power-of-two square), read back as the beams' hit textures, which the beam tree (beam-render) needs
//! for the next level's beams. Where the device has 64-bit atomics, one compute pass
//! (`shaders/beam_texels.wgsl`, an invocation per texel) finds the same hits instead of the draws
//! and the gather: a compute GPU rasterizes on few of its cores, a software one on one thread.
//! A level the composite shades is kept on the GPU ([`super::GpuLevelPoints`]) and returned as a
//! value ([`LevelKept`]) for the frame to hand on.

use super::beam::GpuBeam;
use super::composite::GpuComposite;
use super::fits::{FitTable, ReadFits, fit_slots};
use super::level::{GpuLevelPoints, HostTexel, KeptLevel, LevelKeep};
use super::lookups::LookupBeams;
use super::page::{AtlasPages, Counters};
use super::page_inputs::{PageInputs, PageMemo, page_key};
use super::prepare::{Preparations, Prepared, prepared};
use super::records::LocateTable;
use super::times::SummedTimes;
use crate::buffers::{checked, map_all, max_binding, output};
use crate::interface::TEXEL_JOB_PAIRS;
use crate::{Gpu, GpuError, texels};
use beam_render::BackendError;
use beam_render::nonlinear::{BeamJob, BeamTexture, KeepLevel, KeptTotals, region_texels};
use beam_render::options::Shading;
use beam_scene::scene::Scene;
use std::cell::Cell;
use std::sync::Arc;
use std::time::Instant;

/// The tree levels' stage on the GPU: the atlas's passes ([`AtlasPages`]) and the level-points
/// pass ([`GpuLevelPoints`]), made with the renderer for one scene, and what one frame's levels
/// leave for the next frame's ([`AtlasMemo`]). It keeps nothing of a frame: a level it keeps it
/// returns ([`LevelKept`]).
pub(super) struct GpuAtlas<'g> {
    pub(super) gpu: &'g Gpu,
    /// The page passes.
    pub(super) pages: AtlasPages<'g>,
    /// The level-points pass (and the composite records of the texels it hands to the host).
    pub(super) level: GpuLevelPoints,
    /// Most pairs a workgroup of the compute pass tests its texels against.
    pub(super) job_pairs: u32,
    /// Whether it keeps the levels' points (and the eye stage the eye's mirror and glass hits)
    /// on the GPU, unless [`super::GpuBeams::reading_levels_back`].
    pub(super) keep_levels: bool,
    /// Across frames: each frame's levels read what the last frame's left and leave their own for
    /// the next. Frames use the renderer in turn ([`render_level`](Self::render_level) takes
    /// `&mut self`), so it is a plain value, lent to one level at a time.
    memo: AtlasMemo,
    /// No candidates (no texel located), where the frame's eye stage kept none.
    no_locate: LocateTable,
    /// Where the stage spent its time, summed over the renderer's life.
    pub(super) times: SummedTimes,
}

/// What one frame's tree levels leave for the next frame's, and the renderer keeps between them
/// (across frames; never a frame's results, only work it can skip): the beams made ready for the
/// atlas, the pages with their inputs uploaded (each of this frame's tree and the last one's), and
/// per tree level the slots its last fit table used and whether it overflowed ([`fit_slots`]).
#[derive(Default)]
struct AtlasMemo {
    preparations: Preparations,
    pages: PageMemo,
    fit_slots: Vec<Option<(usize, bool)>>,
}

/// A tree level the atlas stage kept on the GPU ([`GpuAtlas::render_level`]): a frame's value,
/// which the frame holds until its composite shades it.
pub(super) struct LevelKept {
    /// Its points on the GPU.
    pub(super) kept: KeptLevel,
    /// On a coarse S mesh, the level as the records of the level above (the eye's, for the first)
    /// look their points up in it, where made.
    pub(super) lookups: Option<LookupBeams>,
    /// What it kept, for the caller.
    pub(super) totals: KeptTotals,
}

/// Where a beam landed: its page and the corner of its region.
struct Placed {
    page: usize,
    x: u32,
    y: u32,
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

impl<'g> GpuAtlas<'g> {
    /// The stage for `scene`: its passes compiled, its triangles uploaded.
    pub(super) fn new(gpu: &'g Gpu, scene: &Scene) -> Result<Self, GpuError> {
        Ok(Self {
            gpu,
            pages: AtlasPages::new(gpu, scene)?,
            level: GpuLevelPoints::new(gpu, scene)?,
            job_pairs: TEXEL_JOB_PAIRS,
            keep_levels: true,
            memo: AtlasMemo::default(),
            no_locate: LocateTable::none(gpu),
            times: SummedTimes::default(),
        })
    }

    /// Whether it finds the atlas's nearest hits by compute.
    pub(super) fn by_compute(&self) -> bool {
        self.pages.by_compute()
    }

    /// The textures of `jobs`, a batch of beams outside a frame's tree (none prepared for the
    /// next frame).
    pub(super) fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, BackendError> {
        Ok(self.render(scene, jobs, None, None, None)?.0)
    }

    /// A level of a frame's tree ([`beam_render::nonlinear::BeamRasterizer::render_level`]), kept
    /// where the composite will shade the tree (exact shading, the level within one texture),
    /// unless [`super::GpuBeams::reading_levels_back`] asked otherwise; its texels located by
    /// `locate` (the candidates the frame's eye stage kept, where it did). Returns the textures
    /// and the level kept, a value for the frame to hold.
    pub(super) fn render_level(
        &mut self,
        scene: &Scene,
        jobs: &[BeamJob<'_>],
        keep: &KeepLevel<'_>,
        locate: Option<&LocateTable>,
    ) -> Result<(Vec<BeamTexture>, Option<LevelKept>), BackendError> {
        if keep.level <= 1 {
            self.memo.preparations.next_frame();
            self.memo.pages.next_frame();
        }
        let shaded_here = keep.options.shading == Shading::Exact && texels::fits(self.gpu, keep.layout.len);
        let keep = (self.keep_levels && shaded_here).then_some(keep);
        // The memo lent to the level (`render` reads the stage's passes through `&self`).
        let mut memo = std::mem::take(&mut self.memo);
        let rendered = self.render(scene, jobs, keep, locate, Some(&mut memo));
        self.memo = memo;
        let (textures, kept) = rendered?;
        let Some(keep) = keep else {
            return Ok((textures, None));
        };
        let mut kept = kept.ok_or(GpuError::Internal("a level to keep was not kept"))?;
        // On a coarse S mesh the records of the level above (the eye's, for the first) look their
        // points up in this one: in the depths written on the GPU, else in every hit read back.
        let lookups = if let Some(depths) = kept.depths.take() {
            let regions = keep.layout.firsts.iter().zip(jobs).map(|(&first, j)| (j.beam, [first, 0, j.size]));
            Some(LookupBeams::on_regions(self.gpu, regions, depths))
        } else if keep.with_hits {
            let beams: Vec<_> = jobs.iter().map(|j| j.beam).zip(&textures).collect();
            checked(self.gpu, || LookupBeams::upload(self.gpu, &beams))?
        } else {
            None
        };
        let records = self.composites_handed_back(keep);
        // Texels whose fits the GPU summed are kept there too.
        let summed: u64 = if kept.fits { kept.host.iter().map(|(_, n)| u64::from(*n)).sum() } else { 0 };
        let totals = KeptTotals { points: kept.points() + summed, curved: kept.curved, records, fits: kept.fits };
        self.times.add(|t| t.levels_kept += 1);
        Ok((textures, Some(LevelKept { kept, lookups, totals })))
    }
}

impl GpuAtlas<'_> {
    /// Into `textures` (level `level`'s, kept as `kept`), the fits summed in `table`; where it
    /// overflowed, the texels it was given instead, read back (and a larger table next frame).
    fn read_fits(
        &self,
        memo: Option<&mut AtlasMemo>,
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
        if let Some(memo) = memo {
            let slots = &mut memo.fit_slots;
            if slots.len() <= level {
                slots.resize(level + 1, None);
            }
            slots[level] = Some(last);
        }
        self.times.add(|t| t.atlas_seconds += start.elapsed().as_secs_f64());
        Ok(())
    }

    /// Whether the composite makes the records of the texels a level kept as `keep` hands back:
    /// on an S mesh whose faces fit one binding (as the eye's records).
    fn composites_handed_back(&self, keep: &KeepLevel<'_>) -> bool {
        GpuComposite::faces_fit(self.gpu, keep.faces)
    }

    /// The textures of `jobs`; with `keep`, the points of the texels from which the tree does not go
    /// on kept on the GPU ([`super::GpuLevelPoints`]), the textures holding only the others' hits
    /// (every hit `keep.with_hits`); with the renderer's `memo`, beams of a frame's tree, each
    /// prepared once for this frame and the next ([`Preparations`]), and pages uploaded once.
    fn render(
        &self,
        scene: &Scene,
        jobs: &[BeamJob<'_>],
        keep: Option<&KeepLevel<'_>>,
        locate: Option<&LocateTable>,
        mut memo: Option<&mut AtlasMemo>,
    ) -> Result<(Vec<BeamTexture>, Option<KeptLevel>), BackendError> {
        let start = Instant::now();
        // Bounding-cone culling (000 App. A) by the BVH's boxes here, triangle by triangle on the
        // GPU (`super::cull`); the beams for the shader from the same bounds, placed on their
        // regions below.
        let before = memo.as_ref().map_or((0, 0), |m| m.preparations.reused());
        let culled = prepared(scene, jobs, memo.as_deref_mut().map(|m| &mut m.preparations));
        let after = memo.as_ref().map_or((0, 0), |m| m.preparations.reused());
        self.times.add(|t| {
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
        let capacity = u64::from(self.pages.side) * u64::from(self.pages.side);
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
            if s > self.pages.side || t > max_texels {
                return Err(GpuError::BeamTooLarge { size: jobs[i].size, page: self.pages.side }.into());
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
            let last = memo.as_ref().and_then(|m| m.fit_slots.get(k.level).copied().flatten());
            FitTable::new(self.gpu, fit_slots(last, jobs.len()), jobs.len(), k.faces, max_binding(self.gpu))
        });
        let locate = locate.unwrap_or(&self.no_locate);
        self.times.add(|t| t.prepare_seconds += start.elapsed().as_secs_f64());
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
            let found = memo.as_mut().map(|m| m.pages.values(vec![page_key(&preps, &regions)], |_| upload()).pop());
            let inputs = found.flatten().unwrap_or_else(upload);
            let pair_count = inputs.pairs as u32;
            let firsts = &inputs.firsts;
            let prepared = start.elapsed().as_secs_f64();
            let unpacking = Cell::new(0.0);
            let with_hits = keep.is_none_or(|k| k.with_hits) && depths.is_none();
            let unpack = |texels: &[[u32; 2]], counts: &[Counters]| {
                let start = Instant::now();
                let texels = with_hits.then_some(texels);
                let out = AtlasPages::unpack(jobs, &members, firsts, texels, counts, by_compute);
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
            let (unpacked, appended) = checked(self.gpu, || {
                self.pages.render_page((&self.level, &self.times), &inputs, page_rows, keep_page.as_ref(), unpack)
            })?;
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
                        let out = AtlasPages::unpack_host_texels(&mut unpacked, bytes);
                        (out, start.elapsed().as_secs_f64())
                    };
                    let (out, unpacking) = checked(self.gpu, || map_all(self.gpu, Vec::new(), sources, unpack))?;
                    out?;
                    self.times.add(|t| {
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
            self.times.add(|t| {
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
            self.read_fits(memo, &table, kept, &mut textures, k.level)?;
        }
        Ok((textures, kept))
    }
}
