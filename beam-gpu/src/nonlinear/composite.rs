//! The final composite of 000 §7.3 on the GPU (`shaders/composite.wgsl`): the radiance flow of a
//! beam tree, deepest level first, with every level's radiance kept on the GPU (an RGBA16F texture,
//! which no storage binding bounds) and only the eye's pixels read back. Each dispatch binds only
//! the S-mesh faces and child regions its records reference, so no buffer grows with the S mesh
//! or a level's beams past one storage binding of the device. Diffuse, glossy and emissive points are
//! shaded by [`PointShader`], mirror and glass points without child beams (past the last level) by
//! the caller, and the `scatter` pass writes both to their texels (4 bytes uploaded a point, its
//! texel): only the texels to composite have records. Host twin: beam-render's `composite_levels`.

use super::display::GpuFrame;
use super::records::{EyeRecords, KeptPoints};
use super::sort::{Outputs, Plan, plan};
use super::whitted::{RestJob, RestPoints};
use crate::buffers::{buffer_entry, compute_pipeline, encode_pass, max_binding, output, storage, uniform, view_entry};
use crate::checks::ShadeChecks;
use crate::raytrace::RayTracer;
use crate::scratch::{Scratch, scratch};
use crate::shade::{PointShader, ShadeInput, ShadeScene, Shaded};
use crate::staging::Staged;
use crate::texels;
use crate::{Gpu, GpuError};
use beam_render::nonlinear::{LevelRadiance, SMesh};
use beam_scene::scene::{Material, Scene};
use bytemuck::{Pod, Zeroable};
use wgpu::WriteOnly;

/// An S-mesh face for the composite.
///
/// WGSL twin: `Face` in `shaders/composite.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuFace {
    /// Vertices (w unused).
    pub v: [[f32; 4]; 3],
    /// Unit vertex normals on the side of the geometric normal (w unused).
    pub n: [[f32; 4]; 3],
    /// The scene triangle's unit geometric normal (w unused).
    pub normal: [f32; 4],
    /// rgb: a mirror's tint; w: a glass's index of refraction, 0 for a mirror.
    pub material: [f32; 4],
}

/// Uniforms of the composite pass.
///
/// WGSL twin: `CompositeParams` in `shaders/composite.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CompositeParams {
    /// Records of the dispatch (`composite`).
    pub records: u32,
    /// Shaded radiances it writes to their texels (`scatter`)...
    pub points: u32,
    /// ...from this element of the shaded radiances on.
    pub first: u32,
    /// Padding.
    pub pad: u32,
}

const _: () = assert!(size_of::<GpuFace>() == 128 && size_of::<CompositeParams>() == 16);

/// "None" in [`CompositeRecord`](super::records::CompositeRecord) ([`crate::interface::NONE`]).
pub use crate::interface::NONE;

/// Shades batches of the points the [`PointShader`] does not (mirrors and glass past the tree): adds
/// the radiance of each job's point `i` to element `first + i` of its buffer of `vec4<f32>`s
/// (zeroed), as [`GpuWhitted::shade_into`](super::GpuWhitted::shade_into) does.
pub type ShadeRest<'a> = dyn Fn(&[RestJob<'_>], &mut ShadeChecks) -> Result<(), GpuError> + 'a;

/// Points kept on the GPU for one level of the radiance flow: shaded by the shading pass (`direct`,
/// the eye's diffuse, glossy and emissive pixels, [`super::GpuEye`], or a kept level's), or by the
/// caller's [`ShadeRest`] (`rest`, a kept level's mirror and glass points past the tree,
/// [`super::KeptLevel`]).
#[derive(Clone, Copy, Default)]
pub struct KeptHere<'a> {
    /// Shaded by the shading pass.
    pub direct: &'a [KeptPoints],
    /// Shaded by the caller.
    pub rest: &'a [KeptPoints],
    /// Composite records made on the GPU, their faces and child beams indexed in the whole S mesh
    /// and the whole level below (the eye's mirror and glass pixels, [`super::GpuEye::records`]),
    /// and the points among them without child beams, shaded by the caller.
    pub records: &'a [EyeRecords],
}

/// Kept points of every level shaded together: their shading, their inputs gathered into one
/// buffer (held with the shading until it is submitted), and per level, per [`KeptPoints`], its
/// first element in it.
type Joined = (Shaded, Scratch, Vec<Vec<u32>>);

/// The format of a level's radiance: rgb as half floats (and an unused alpha), 8 bytes a texel.
const RADIANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The composite's passes (the frame's last stage), compiled with the renderer for its life;
/// they keep nothing of a frame: what they composite is handed to [`GpuComposite::run`].
pub struct GpuComposite {
    pipeline: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
}

impl GpuComposite {
    /// Compile the pass.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(Self {
            pipeline: compute_pipeline(gpu, "composite", "composite")?,
            scatter: compute_pipeline(gpu, "composite", "scatter")?,
        })
    }

    /// True when every level's radiance fits one texture of the device (a level is a texture, not a
    /// storage buffer, so the storage bindings do not bound it), and where the GPU makes a level's
    /// records ([`LevelRadiance::node_children`]), the regions of the level below fit one binding.
    #[must_use]
    pub fn fits(gpu: &Gpu, levels: &[LevelRadiance]) -> bool {
        let below = levels.iter().skip(1).map(|l| l.regions.len()).chain([0]);
        let records_fit =
            |(l, below): (&LevelRadiance, usize)| l.node_children.is_empty() || below as u64 * 8 <= max_binding(gpu);
        levels.iter().all(|l| texels::fits(gpu, l.len)) && levels.iter().zip(below).all(records_fit)
    }

    /// True when `faces` S-mesh faces fit one storage binding, as the composite of records made on
    /// the GPU (the eye's, a level's) binds them.
    pub(crate) fn faces_fit(gpu: &Gpu, faces: usize) -> bool {
        faces as u64 * size_of::<GpuFace>() as u64 <= max_binding(gpu)
    }

    /// Records of one dispatch: the records (64 bytes each), the S-mesh faces they reference (128
    /// bytes each, compacted to the dispatch's own) and the regions of their child beams (8 bytes,
    /// at most two a record) each within one storage binding, as are the shading pass's inputs.
    pub(crate) fn records_per_dispatch(gpu: &Gpu) -> usize {
        let by_faces = (max_binding(gpu) / size_of::<GpuFace>() as u64) as usize;
        by_faces.min(PointShader::max_points(gpu)).clamp(1, 1 << 20)
    }

    /// How a level's radiance is used: read by the level above, written by the passes, copied out.
    const LEVEL_USAGE: wgpu::TextureUsages = wgpu::TextureUsages::TEXTURE_BINDING
        .union(wgpu::TextureUsages::STORAGE_BINDING)
        .union(wgpu::TextureUsages::COPY_SRC);

    /// A level's radiance: `len` texels ([`crate::texels`]).
    fn level_texture(gpu: &Gpu, len: usize) -> wgpu::Texture {
        texels::texture(gpu, "level radiance", len, RADIANCE_FORMAT, Self::LEVEL_USAGE)
    }

    /// The radiance flow of `levels` (`levels[0]` the eye's view) on the GPU: the eye's pixels,
    /// kept in a texture of `shape` (width, height) where given and it holds the eye's level.
    /// Points the [`PointShader`] shades are shaded on the GPU (`spp` shadow rays per area light,
    /// the scene's shading and caustics `prepared` by [`PointShader::prepare`]), the others by
    /// `rest`; so are the points kept on the GPU (not in `levels`), `kept[d]` those of `levels[d]`
    /// (the eye's by [`GpuEye`](super::GpuEye), the tree's by [`super::GpuLevelPoints`]).
    /// Every level's radiance is a texture; its texels go in dispatches of at most
    /// `records_per_dispatch` texels, each binding only the faces and child regions its records
    /// reference. Every shading (`rest`'s too) is given `checks`. Call inside
    /// [`crate::buffers::checked`].
    pub fn run(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        shader: &PointShader,
        (scene, smesh): (&Scene, &SMesh),
        prepared: &ShadeScene,
        spp: u32,
        levels: &[LevelRadiance],
        kept: &[KeptHere<'_>],
        rest: &ShadeRest<'_>,
        shape: Option<(u32, u32)>,
        checks: &mut ShadeChecks,
    ) -> Result<GpuFrame, GpuError> {
        let all_faces = gpu_faces(scene, smesh);
        let chunk = Self::records_per_dispatch(gpu);
        // Every level's kept mirror and glass points past the tree first, in one set of Whitted
        // waves (they need nothing of the tree's radiance): per level, the points and their radiance.
        let rests: Vec<Vec<(&KeptPoints, wgpu::Buffer)>> = kept
            .iter()
            .map(|here| {
                let records_rest = here.records.iter().map(|r| &r.rest);
                let points = here.rest.iter().chain(records_rest).filter(|k| k.count > 0);
                points.map(|k| (k, output(gpu, "radiance", u64::from(k.count) * 16))).collect()
            })
            .collect();
        let jobs: Vec<RestJob<'_>> = rests
            .iter()
            .flatten()
            .map(|(k, radiance)| RestJob { points: RestPoints::Gpu(&k.inputs, k.count as usize), radiance, first: 0 })
            .collect();
        if !jobs.is_empty() {
            rest(&jobs, checks)?;
        }
        // Every level's kept points the shading pass shades (they need nothing of the tree's
        // radiance either), in one shading where they fit one.
        // It, and the levels' shadings, scatters and records, wait in one encoder (their shadings
        // held with it) until work of the host's comes between.
        let new_encoder = || gpu.device.create_command_encoder(&Default::default());
        let (mut encoder, mut held) = (new_encoder(), Vec::new());
        let joined = Self::shade_joined(gpu, (tracer, shader, prepared, spp), kept, checks, &mut encoder)?;
        let mut below = Self::level_texture(gpu, 0);
        let mut below_regions: &[(u32, u32)] = &[];
        let mut len = 0;
        for (depth, level) in levels.iter().enumerate().rev() {
            len = level.len;
            let radiance = match shape {
                Some((width, height)) if depth == 0 && width as usize * height as usize == len => {
                    texels::texture_2d(gpu, "frame radiance", (width, height), RADIANCE_FORMAT, Self::LEVEL_USAGE)
                }
                _ => Self::level_texture(gpu, len),
            };
            let views = (below.create_view(&Default::default()), radiance.create_view(&Default::default()));
            // The points kept on the GPU: shaded and written to their texels.
            let here = kept.get(depth).copied().unwrap_or_default();
            // Their shadings (one by one where not together), scatters and the records made on the
            // GPU.
            let own = match joined {
                Some(_) => Vec::new(),
                None => here
                    .direct
                    .iter()
                    .map(|k| {
                        let points = (&*k.inputs, k.count as usize, 0);
                        shader.shade_inputs(gpu, tracer, prepared, spp, points, Some(checks), &mut encoder)
                    })
                    .collect::<Result<Vec<_>, GpuError>>()?,
            };
            let mut scatter = |(shaded, first): (&wgpu::Buffer, u32), k: &KeptPoints| {
                let params = CompositeParams { records: 0, points: k.count, first, pad: 0 };
                self.encode_scatter(gpu, &mut encoder, &params, shaded, &views.1, &k.targets);
            };
            for (i, k) in here.direct.iter().enumerate() {
                match &joined {
                    Some((shaded, _, firsts)) => scatter((&shaded.radiance, firsts[depth][i]), k),
                    None => scatter((&own[i].radiance, 0), k),
                }
            }
            for (k, shaded) in rests.get(depth).into_iter().flatten() {
                scatter((shaded, 0), k);
            }
            if !here.records.is_empty() {
                // Every face and child region, each within one binding.
                let regions: Vec<[u32; 2]> = below_regions.iter().map(|&(first, size)| [first, size]).collect();
                let bytes = (regions.len() * 8).max(all_faces.len() * size_of::<GpuFace>());
                if bytes as u64 > max_binding(gpu) {
                    return Err(GpuError::Internal("the S mesh or the level below past one binding"));
                }
                let faces = storage(gpu, "faces", &all_faces, wgpu::BufferUsages::empty());
                let regions = storage(gpu, "regions", &regions, wgpu::BufferUsages::empty());
                for r in here.records {
                    let params = CompositeParams { records: r.count, points: 0, first: 0, pad: 0 };
                    self.encode_records(gpu, &mut encoder, &params, &r.records, (&faces, &regions), &views);
                }
            }
            held.extend(own);
            for texels in level.texels.chunks(chunk) {
                // Points not composited: on the GPU where the point shader shades them, else by
                // `rest`; the composited ones' records.
                let plan = plan(scene, texels, (all_faces.len(), below_regions.len()))?;
                let [direct, others, composited] = plan.totals();
                let mut other = vec![ShadeInput::zeroed(); others];
                // One pass writes the shading pass's inputs, the targets and the records straight
                // into the queue's staging memory, and the caller's points into `other`.
                let none = wgpu::BufferUsages::empty();
                let mut inputs = Staged::new(gpu, "shade points", direct, none);
                let mut targets = Staged::new(gpu, "targets", direct + others, none);
                let mut records = Staged::new(gpu, "records", composited, none);
                let out = Outputs {
                    direct: inputs.slots(),
                    other: WriteOnly::from_mut(&mut other[..]),
                    targets: targets.slots(),
                    records: records.slots(),
                };
                plan.fill((scene, smesh), texels, out)?;
                let (inputs, targets, records_buffer) = (inputs.finish(gpu), targets.finish(gpu), records.finish(gpu));
                let points = (&inputs, direct, others);
                let shaded = shader.shade_inputs(gpu, tracer, prepared, spp, points, Some(checks), &mut encoder)?;
                let shaded = &shaded.radiance;
                if !other.is_empty() {
                    // What waits, and this radiance cleared and shaded, before the Whitted rays add
                    // to it.
                    gpu.submit([std::mem::replace(&mut encoder, new_encoder()).finish()]);
                    held.clear();
                    rest(&[RestJob { points: RestPoints::Host(&other), radiance: shaded, first: direct }], checks)?;
                }
                let Plan { faces, regions, .. } = plan;
                let chunk_faces: Vec<GpuFace> = faces.iter().map(|&f| all_faces[f as usize]).collect();
                let chunk_regions: Vec<[u32; 2]> = regions
                    .iter()
                    .map(|&b| {
                        let (first, size) = below_regions[b as usize];
                        [first, size]
                    })
                    .collect();
                let points = (direct + others) as u32;
                let params = CompositeParams { records: composited as u32, points, first: 0, pad: 0 };
                self.encode_scatter(gpu, &mut encoder, &params, shaded, &views.1, &targets);
                let faces = storage(gpu, "faces", &chunk_faces, wgpu::BufferUsages::empty());
                let regions = storage(gpu, "regions", &chunk_regions, wgpu::BufferUsages::empty());
                self.encode_records(gpu, &mut encoder, &params, &records_buffer, (&faces, &regions), &views);
                gpu.submit([std::mem::replace(&mut encoder, new_encoder()).finish()]);
                held.clear();
            }
            below_regions = &level.regions;
            below = radiance;
        }
        gpu.submit([encoder.finish()]);
        drop(held);
        Ok(GpuFrame { texture: below, len })
    }

    /// The points of `kept` the shading pass shades ([`KeptHere::direct`], every level's), shaded
    /// together (given `checks`, added to `encoder`, [`PointShader::shade_inputs`]) where there
    /// are several and they fit one shading. `None` where they go one by one.
    fn shade_joined(
        gpu: &Gpu,
        (tracer, shader, prepared, spp): (&RayTracer, &PointShader, &ShadeScene, u32),
        kept: &[KeptHere<'_>],
        checks: &mut ShadeChecks,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Option<Joined>, GpuError> {
        let all = || kept.iter().flat_map(|h| h.direct).filter(|k| k.count > 0);
        let total: usize = all().map(|k| k.count as usize).sum();
        if all().count() < 2 || total > PointShader::max_points(gpu) {
            return Ok(None);
        }
        let each = size_of::<ShadeInput>() as u64;
        let inputs = scratch(gpu, "shade points", total as u64 * each);
        let mut at = 0u32;
        let mut firsts = Vec::with_capacity(kept.len());
        for here in kept {
            let mut level = Vec::with_capacity(here.direct.len());
            for k in here.direct {
                level.push(at);
                encoder.copy_buffer_to_buffer(&k.inputs, 0, &inputs, u64::from(at) * each, u64::from(k.count) * each);
                at += k.count;
            }
            firsts.push(level);
        }
        let shaded = shader.shade_inputs(gpu, tracer, prepared, spp, (&inputs, total, 0), Some(checks), encoder)?;
        Ok(Some((shaded, inputs, firsts)))
    }

    /// Add to `encoder` the pass that writes `params.points` shaded points (`shaded`) to their
    /// `targets` texels of the level's radiance (`radiance`).
    fn encode_scatter(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        params: &CompositeParams,
        shaded: &wgpu::Buffer,
        radiance: &wgpu::TextureView,
        targets: &wgpu::Buffer,
    ) {
        let uniform = uniform(gpu, "composite params", bytemuck::bytes_of(params));
        let entries =
            [buffer_entry(0, &uniform), buffer_entry(3, shaded), view_entry(6, radiance), buffer_entry(7, targets)];
        encode_pass(gpu, encoder, &self.scatter, params.points, &entries);
    }

    /// Add to `encoder` the pass that composites `params.records` records from the child regions
    /// of the level below (`views.0`, regions and faces as the records index them) into the level's
    /// radiance (`views.1`).
    fn encode_records(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        params: &CompositeParams,
        records: &wgpu::Buffer,
        (faces, regions): (&wgpu::Buffer, &wgpu::Buffer),
        views: &(wgpu::TextureView, wgpu::TextureView),
    ) {
        let uniform = uniform(gpu, "composite params", bytemuck::bytes_of(params));
        let entries = [
            buffer_entry(0, &uniform),
            buffer_entry(1, records),
            buffer_entry(2, faces),
            view_entry(4, &views.0),
            buffer_entry(5, regions),
            view_entry(6, &views.1),
        ];
        encode_pass(gpu, encoder, &self.pipeline, params.records, &entries);
    }
}

/// The faces of `smesh` for the shader.
fn gpu_faces(scene: &Scene, smesh: &SMesh) -> Vec<GpuFace> {
    smesh
        .faces
        .iter()
        .map(|f| GpuFace {
            v: f.v.map(|v| v.extend(0.0).to_array()),
            n: f.n.map(|n| n.extend(0.0).to_array()),
            normal: f.normal.extend(0.0).to_array(),
            material: match scene.material(f.prim) {
                Material::Mirror { tint, .. } => tint.extend(0.0).to_array(),
                Material::Glass { ior } => [1.0, 1.0, 1.0, ior],
                _ => [0.0; 4],
            },
        })
        .collect()
}
