//! A level of the beam tree kept on the GPU (`shaders/level_points.wgsl`): after an atlas page's
//! nearest hits, the texels that hit a triangle on which the tree goes on (a mirror or glass face
//! that spawns the next level's beams) go to the host, which builds the next level and the
//! composite from them (where the GPU composites them itself, only their fits go, summed per beam
//! and face: [`super::FitTable`]); every other texel that hit becomes a shading input where it lies, at its
//! place in the level's radiance, so that neither its hit nor its point crosses to the host and
//! back (000 §7.3 keeps the tree's texels on the GPU). On the tree's last level no triangle goes
//! on: the whole level stays. The texels for the host carry their points, so the host evaluates
//! no texel ray for them. The composite shades the kept points ([`super::GpuComposite::run`]):
//! the diffuse, glossy and emissive ones by the shading pass, the others (mirror and glass past
//! the tree) by the Whitted rays. CPU twin: the host's texel hits (beam-render's `Tree::build`)
//! sorted as `sort.rs` sorts a level's texels.

use super::composite::GpuComposite;
use super::fits::FitTable;
use super::records::{CoarseBindings, EyeRecords, KeptPoints, LocateTable, RecordOutputs, triangle_kinds};
use super::whitted::GpuWhitted;
use crate::buffers::{buffer_entry, compute_pipeline, encode_pass, map_all, output, read_all, storage, uniform};
use crate::interface::LEVEL_CONTINUES;
use crate::scratch::{Scratch, scratch};
use crate::shade::ShadeInput;
use crate::{Gpu, GpuError};
use beam_math::glam::Vec3;
use beam_render::nonlinear::{LevelLayout, NodeChildren, ShadePoint, TexelPoint, TexelRadiance};
use beam_scene::scene::Scene;
use bytemuck::{Pod, Zeroable};

/// Uniforms of one dispatch of the level-points pass.
///
/// WGSL twin: `LevelParams` in `shaders/level_points.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LevelParams {
    /// The dispatch's first texel among the page's regions.
    pub first: u32,
    /// Texels of the dispatch.
    pub count: u32,
    /// 1 where the texels' words are inverted (nearest hits by compute), else 0.
    pub inverted: u32,
    /// Beams on the page.
    pub beams: u32,
    /// `level_records`: the scene's diagonal, where a texel's ray leaves the scene (beam-render's
    /// `reproject`).
    pub far: f32,
    /// `level_points`: 1 where every texel's depth is written for the lookups of the level
    /// above (under a coarse S mesh), else 0.
    pub depths: u32,
    /// `level_points`: slots of the level's fit table ([`FitTable`]), where it sums the fits
    /// (else 0: the host does); `level_records`: not 0 where the GPU summed them, and it counts
    /// the texels on curved triangles without child beams at their face, which the host does not
    /// see.
    pub fits: u32,
    /// Faces of the S mesh (the fit table's keys).
    pub faces: u32,
}

/// What one dispatch appended.
///
/// WGSL twin: `LevelCounts` in `shaders/level_points.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LevelCounts {
    /// Points appended for the shading pass.
    pub direct: u32,
    /// Points appended for the Whitted rays.
    pub other: u32,
    /// Points on curved (smooth-normal) triangles, of either list.
    pub curved: u32,
    /// Texels appended for the host.
    pub host: u32,
}

/// A texel handed to the host: its hit, with its ray's point and unit direction found where the
/// GPU found the hit.
///
/// WGSL twin: `HostTexel` in `shaders/level_points.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct HostTexel {
    /// The hit point.
    pub p: [f32; 3],
    /// The scene triangle hit.
    pub prim: u32,
    /// Unit direction of the texel's ray.
    pub d: [f32; 3],
    /// The bits of the hit's ray parameter t.
    pub t: u32,
    /// Its beam on the page.
    pub beam: u32,
    /// Its texel in the beam's square (`y · size + x`).
    pub texel: u32,
    /// Its beam in the level.
    pub node: u32,
    /// The S-mesh face its point lies nearest among its triangle's candidates (a fine triangle's
    /// own face); [`NONE`](crate::interface::NONE) for none (no candidates bound: the host
    /// locates it).
    pub face: u32,
}

const _: () = assert!(size_of::<LevelParams>() == 32 && size_of::<LevelCounts>() == 16);
const _: () = assert!(size_of::<HostTexel>() == 48);

/// One atlas page as the pass reads it: its beams, their first texels in `texels` (and the total),
/// its regions' texels, and whether their words are inverted.
pub(super) struct LevelPage<'a> {
    pub beams: (&'a wgpu::Buffer, usize),
    pub firsts: &'a wgpu::Buffer,
    pub texels: (&'a wgpu::Buffer, u32),
    pub inverted: bool,
}

/// One dispatch's lists, their counts on the GPU until read back.
pub(super) struct Appended {
    direct: (Scratch, Scratch),
    other: (Scratch, Scratch),
    /// The texels for the host, [`HostTexel`] each.
    pub host: Scratch,
    /// [`LevelCounts`], zeroed by wgpu.
    pub counts: wgpu::Buffer,
}

/// The points of a level kept on the GPU (per frame, in the frame's kept value), until the
/// composite shades them.
#[derive(Default)]
pub struct KeptLevel {
    /// The tree level (1 for the eye's children).
    pub level: usize,
    /// Per dispatch, the points the shading pass shades.
    pub direct: Vec<KeptPoints>,
    /// Per dispatch, the points the Whitted rays shade (at most [`GpuWhitted::per_dispatch`] each).
    pub other: Vec<KeptPoints>,
    /// Points on curved triangles.
    pub curved: u64,
    /// Per dispatch, the texels handed to the host ([`HostTexel`]s) and how many, kept where the
    /// GPU composites them too ([`GpuLevelPoints::records`]).
    pub host: Vec<(Scratch, u32)>,
    /// The level's layout, for the seeds of points read back ([`KeptLevel::read_back`]).
    layout: LevelLayout,
    /// Under a coarse S mesh, its texels' depths, written on the GPU for the lookups of the level
    /// above.
    pub depths: Option<wgpu::Buffer>,
    /// Whether the GPU summed the fits of the texels for the host ([`FitTable`]), which then read
    /// none back.
    pub fits: bool,
}

impl KeptLevel {
    /// An empty kept level `level` of `layout`.
    pub(super) fn new(level: usize, layout: &LevelLayout) -> Self {
        Self { level, layout: layout.clone(), ..Self::default() }
    }

    /// Points kept.
    #[must_use]
    pub fn points(&self) -> u64 {
        self.direct.iter().chain(&self.other).map(|k| u64::from(k.count)).sum()
    }

    /// Add the lists of `appended`, whose counts were read back as `counts`; the texels for the
    /// host too where `with_host` (they are the caller's otherwise).
    pub(super) fn add(&mut self, appended: Vec<Appended>, counts: &[LevelCounts], with_host: bool) {
        for (a, c) in appended.into_iter().zip(counts) {
            let kept = |(inputs, targets), count| KeptPoints { inputs, targets, count };
            self.direct.push(kept(a.direct, c.direct));
            self.other.push(kept(a.other, c.other));
            self.curved += u64::from(c.curved);
            if with_host && c.host > 0 {
                self.host.push((a.host, c.host));
            }
        }
    }

    /// The texels handed to the host, read back: per beam of the level, in texel order.
    pub(super) fn host_points(&self, gpu: &Gpu) -> Result<Vec<Vec<TexelPoint>>, GpuError> {
        let size = size_of::<HostTexel>() as u64;
        let sources = self.host.iter().map(|(buffer, n)| (&**buffer, u64::from(*n) * size));
        let ends = self.layout.firsts.iter().skip(1).copied().chain([self.layout.len as u32]);
        // A region of size² texels.
        let sizes: Vec<u32> = ends.zip(&self.layout.firsts).map(|(end, first)| (end - first).isqrt()).collect();
        map_all(gpu, Vec::new(), sources, |bytes| host_points(bytes, &sizes, |h| h.node))?
    }

    /// The points as texels of the level's radiance, read back (for a frame the caller shades after
    /// all), each with the seed the host gives it: its beam's face triangle `<< 32 |` its texel in
    /// the beam's region (the beam the one whose region holds its texel, by the layout).
    pub(super) fn read_back(&self, gpu: &Gpu) -> Result<Vec<TexelRadiance>, GpuError> {
        let lists = || self.direct.iter().chain(&self.other);
        let inputs = read_all::<ShadeInput>(
            gpu,
            Vec::new(),
            lists().map(|k| (&*k.inputs, u64::from(k.count) * size_of::<ShadeInput>() as u64)),
        )?;
        let targets = read_all::<u32>(gpu, Vec::new(), lists().map(|k| (&*k.targets, u64::from(k.count) * 4)))?;
        let firsts = &self.layout.firsts;
        inputs
            .iter()
            .zip(targets)
            .map(|(s, texel)| {
                let beam = firsts.partition_point(|&f| f <= texel).checked_sub(1);
                let beam = beam.ok_or_else(|| GpuError::Internal("a kept point before the level's first beam"))?;
                let seed = u64::from(self.layout.prims[beam]) << 32 | u64::from(texel - firsts[beam]);
                let point = ShadePoint { prim: s.prim, p: Vec3::from_array(s.p), d: Vec3::from_array(s.d), seed };
                Ok(TexelRadiance { texel, point, composite: None })
            })
            .collect()
    }
}

/// The texels listed as [`HostTexel`]s in `host` (bytes as read back, unpacked where they are
/// mapped) as points, per beam (`beam_of` a texel's, of beams whose regions have `sizes` texels a
/// side), each beam's in texel order.
pub(super) fn host_points(
    host: &[u8],
    sizes: &[u32],
    beam_of: impl Fn(&HostTexel) -> u32,
) -> Result<Vec<Vec<TexelPoint>>, GpuError> {
    // Mapped ranges start 8-byte aligned; a copy where the bytes are not aligned all the same.
    let copied: Vec<HostTexel>;
    let host: &[HostTexel] = match bytemuck::try_cast_slice(host) {
        Ok(host) => host,
        Err(_) => {
            copied = bytemuck::pod_collect_to_vec(host);
            &copied
        }
    };
    // Counted first: each beam's points grow to their size once.
    let mut counts = vec![0usize; sizes.len()];
    for h in host {
        *counts.get_mut(beam_of(h) as usize).ok_or(GpuError::Internal("a texel for the host past its beams"))? += 1;
    }
    let mut points: Vec<Vec<TexelPoint>> = counts.into_iter().map(Vec::with_capacity).collect();
    for h in host {
        // Every beam is within `sizes`: counted above.
        let b = beam_of(h) as usize;
        if h.texel >= sizes[b] * sizes[b] {
            return Err(GpuError::Internal("a texel past its region"));
        }
        let (p, d) = (Vec3::from_array(h.p), Vec3::from_array(h.d));
        points[b].push(TexelPoint { texel: h.texel, prim: h.prim, p, d, face: h.face });
    }
    // Appended by atomics in no set order; a region's texels are distinct. (Tens of texels a
    // region: sorted here, not handed to the workers.)
    for p in &mut points {
        p.sort_unstable_by_key(|t| t.texel);
    }
    Ok(points)
}

/// The level-points pass, and the composite records of the texels it hands to the host: compiled
/// with the renderer for one scene, for its life; it keeps nothing of a frame.
pub struct GpuLevelPoints {
    pipeline: wgpu::ComputePipeline,
    records: wgpu::ComputePipeline,
    /// Per scene triangle: [`LEVEL_PLAIN`] where the shading pass shades it, `|` [`LEVEL_CURVED`]
    /// where its normals are interpolated.
    kinds: Vec<u32>,
    /// No depths to write, no fits to sum (a binding is never empty).
    no_depths: wgpu::Buffer,
    no_fits: wgpu::Buffer,
}

/// How a page's texels are kept ([`GpuLevelPoints::encode`]).
pub(super) struct LevelKeep<'a> {
    /// Per beam of the page: its first texel in the level's radiance, its face's scene triangle,
    /// its index in the level, and 0.
    pub placed: &'a [[u32; 4]],
    /// The triangles' kinds ([`GpuLevelPoints::kinds`]).
    pub kinds: &'a wgpu::Buffer,
    /// Whether the host reads every hit back.
    pub with_hits: bool,
    /// The S mesh's candidates and corners, which locate the texels for the host and their fits
    /// (none where the eye's view kept no hits).
    pub locate: &'a LocateTable,
    /// Where given, the level's depths (`f32` per texel of its radiance), written for the lookups
    /// of the level above ([`super::LookupBeams`]).
    pub depths: Option<&'a wgpu::Buffer>,
    /// Where given, the table the fits of the texels for the host are summed in.
    pub fits: Option<&'a FitTable>,
}

impl GpuLevelPoints {
    /// Compile the pass for `scene`'s triangles.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        Ok(Self {
            pipeline: compute_pipeline(gpu, "level_points", "level_points")?,
            records: compute_pipeline(gpu, "level_points", "level_records")?,
            kinds: triangle_kinds(scene),
            no_depths: output(gpu, "no depths", 4),
            no_fits: output(gpu, "no fits", 4),
        })
    }

    /// The triangles' kinds for a level, [`LEVEL_CONTINUES`] where `continues` says the tree goes
    /// on from a triangle, uploaded.
    pub(super) fn kinds(&self, gpu: &Gpu, continues: &[bool]) -> wgpu::Buffer {
        let on = |p: usize| if continues.get(p) == Some(&true) { LEVEL_CONTINUES } else { 0 };
        let kinds: Vec<u32> = self.kinds.iter().enumerate().map(|(p, k)| k | on(p)).collect();
        storage(gpu, "triangle kinds", &kinds, wgpu::BufferUsages::empty())
    }

    /// Texels one dispatch takes: its lists hold as many points as the shading pass, a composite
    /// dispatch and one Whitted dispatch take.
    pub(super) fn per_dispatch(gpu: &Gpu) -> usize {
        GpuComposite::records_per_dispatch(gpu).min(GpuWhitted::per_dispatch(gpu)).max(1)
    }

    /// The pass over every texel of `page`, kept as `keep` says, added to `encoder` in dispatches
    /// of at most [`Self::per_dispatch`] texels. The dispatches' lists, their counts to be read
    /// back.
    pub(super) fn encode(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        page: &LevelPage<'_>,
        keep: &LevelKeep<'_>,
    ) -> Vec<Appended> {
        let placed = storage(gpu, "placed beams", keep.placed, wgpu::BufferUsages::empty());
        let depths = keep.depths.unwrap_or(&self.no_depths);
        let (fits, (slots, faces)) = keep.fits.map_or((&self.no_fits, (0, 0)), |t| (t.buffer(), t.params()));
        let (texels, count) = page.texels;
        let chunk = Self::per_dispatch(gpu);
        (0..count as usize)
            .step_by(chunk)
            .map(|first| {
                let n = chunk.min(count as usize - first);
                let list = |label| {
                    (
                        scratch(gpu, label, (n * size_of::<ShadeInput>()) as u64),
                        scratch(gpu, "level targets", n as u64 * 4),
                    )
                };
                let out = Appended {
                    direct: list("level points"),
                    other: list("level points past the tree"),
                    host: scratch(gpu, "level texels for the host", (n * size_of::<HostTexel>()) as u64),
                    counts: output(gpu, "level counts", size_of::<LevelCounts>() as u64),
                };
                let params = LevelParams {
                    first: first as u32,
                    count: n as u32,
                    inverted: u32::from(page.inverted),
                    beams: page.beams.1 as u32,
                    far: 0.0,
                    depths: u32::from(keep.depths.is_some()),
                    fits: slots,
                    faces,
                };
                let params = uniform(gpu, "level params", bytemuck::bytes_of(&params));
                let entries = [
                    buffer_entry(0, &params),
                    buffer_entry(1, page.beams.0),
                    buffer_entry(2, page.firsts),
                    buffer_entry(3, texels),
                    buffer_entry(4, &placed),
                    buffer_entry(5, keep.kinds),
                    buffer_entry(6, &out.direct.0),
                    buffer_entry(7, &out.direct.1),
                    buffer_entry(8, &out.other.0),
                    buffer_entry(9, &out.other.1),
                    buffer_entry(10, &out.counts),
                    buffer_entry(11, &out.host),
                    buffer_entry(18, keep.locate.candidates()),
                    buffer_entry(19, keep.locate.corners()),
                    buffer_entry(24, depths),
                    buffer_entry(25, fits),
                ];
                encode_pass(gpu, encoder, &self.pipeline, n as u32, &entries);
                out
            })
            .collect()
    }

    /// The composite records of the texels `kept` handed to the host (`face_of` per scene
    /// triangle: its face where it is a fine one, else [`NONE`](crate::interface::NONE)), from the
    /// child beams of the faces each beam's texels hit (`children`), once the next level is built;
    /// under a coarse face, where the texel's own scattered rays read them (`coarse`, its child
    /// level the next); per dispatch, with the points of faces without child beams (or whose child
    /// beams do not hold their rays) for the Whitted rays. Host twin: beam-render's `Tree::composite`.
    pub fn records(
        &self,
        gpu: &Gpu,
        kept: &KeptLevel,
        (face_of, children): (&wgpu::Buffer, &NodeChildren),
        coarse: &CoarseBindings<'_>,
    ) -> Result<Vec<EyeRecords>, GpuError> {
        if kept.host.is_empty() {
            return Ok(Vec::new());
        }
        let none = wgpu::BufferUsages::empty();
        let nodes: Vec<[u32; 2]> = kept.layout.firsts.iter().zip(&kept.layout.prims).map(|(&f, &p)| [f, p]).collect();
        let nodes = storage(gpu, "level beams", &nodes, none);
        let firsts = storage(gpu, "child firsts", &children.firsts, none);
        let entries: Vec<[u32; 4]> = children.entries.iter().map(|&[f, r, t]| [f, r, t, 0]).collect();
        let entries = storage(gpu, "child entries", &entries, none);
        let mut encoders = Vec::new();
        let mut outs = Vec::new();
        for (host, count) in &kept.host {
            let fits = u32::from(kept.fits);
            let params = LevelParams {
                first: 0,
                count: *count,
                inverted: 0,
                beams: 0,
                far: coarse.far,
                depths: 0,
                fits,
                faces: 0,
            };
            let params = uniform(gpu, "level params", bytemuck::bytes_of(&params));
            let out = RecordOutputs::new(gpu, *count as usize);
            let bound = [
                buffer_entry(0, &params),
                buffer_entry(5, coarse.kinds),
                buffer_entry(8, &out.inputs),
                buffer_entry(9, &out.targets),
                buffer_entry(11, host),
                buffer_entry(12, face_of),
                buffer_entry(13, &nodes),
                buffer_entry(14, &firsts),
                buffer_entry(15, &entries),
                buffer_entry(16, &out.records),
                buffer_entry(17, &out.counts),
            ];
            let bound: Vec<_> = bound.into_iter().chain(coarse.entries(18)).collect();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            encode_pass(gpu, &mut encoder, &self.records, *count, &bound);
            encoders.push(encoder.finish());
            outs.push(out);
        }
        RecordOutputs::read(gpu, encoders, outs)
    }
}
