//! The coarse S mesh's lookups on the GPU (`shaders/lookups.wgsl`): per point of a fine surface
//! under a coarse face (000 §7.1), where it reads a child beam for its own scattered ray, by
//! Newton's method on the beam's S^n rays and the texels' depths: beam-render's `reproject` in f32
//! (its projections checked by `gpu_lookup_projections_equal_cpu`, its images by
//! `gpu_coarse_smesh_equals_cpu`).

use super::beam::GpuBeam;
use crate::buffers::{checked, compute_pipeline, max_binding, output, read_back, storage};
use crate::interface::WORKGROUP_SIZE;
use crate::staging::{Slots, Staged, split_by_counts};
use crate::{Gpu, GpuError};
use beam_math::glam::Vec3;
use beam_render::nonlinear::{Beam, BeamTexture, LookupJob};
use beam_render::parallel::piece_len;
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

/// One lookup for the shader ([`LookupJob`]).
///
/// WGSL twin: `LookupJob` in `shaders/lookups.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLookupJob {
    /// The point.
    pub p: [f32; 3],
    /// The child beam, an index into the dispatch's beams.
    pub beam: u32,
    /// The point's scattered unit direction.
    pub truth: [f32; 3],
    /// Where its ray leaves the scene.
    pub far: f32,
    /// Its barycentric coordinates on the face.
    pub w: [f32; 3],
    /// Padding.
    pub pad: u32,
}

const _: () = assert!(size_of::<GpuLookupJob>() == 48);

impl From<&LookupJob> for GpuLookupJob {
    fn from(j: &LookupJob) -> Self {
        Self { p: j.p.to_array(), beam: j.beam, truth: j.truth.to_array(), far: j.far, w: j.w.to_array(), pad: 0 }
    }
}

/// The compiled lookup pipeline, for the renderer's life; it keeps nothing between calls.
pub struct GpuLookups {
    pipeline: wgpu::ComputePipeline,
}

impl GpuLookups {
    /// Compile `lookups.wgsl`.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(Self { pipeline: compute_pipeline(gpu, "lookups", "lookups")? })
    }

    /// Each job's coordinates on its beam's base and how far outside the base its last projection
    /// lay (beam-render's `reproject`), the beams `beams` with their textures; `None` where the beams'
    /// texels or the jobs do not fit one storage binding (the host looks them up).
    pub fn run(
        &self,
        gpu: &Gpu,
        beams: &[(&Beam, &BeamTexture)],
        jobs: &[LookupJob],
    ) -> Result<Option<Vec<(Vec3, f32)>>, GpuError> {
        if jobs.is_empty() {
            return Ok(Some(Vec::new()));
        }
        if jobs.len() * size_of::<GpuLookupJob>() > max_binding(gpu) as usize {
            return Ok(None);
        }
        let Some(level) = LookupBeams::upload(gpu, beams)? else { return Ok(None) };
        // The jobs, written in place, in parallel.
        let none = wgpu::BufferUsages::empty();
        let mut gpu_jobs = Staged::<GpuLookupJob>::new(gpu, "lookup jobs", jobs.len(), none);
        let piece = piece_len(jobs.len());
        let pieces = split_by_counts(gpu_jobs.slots(), jobs.chunks(piece).map(<[_]>::len))
            .ok_or(GpuError::Internal("lookup jobs past their buffer"))?;
        pieces.into_par_iter().zip(jobs.par_chunks(piece)).for_each(|(Slots(out), jobs)| {
            out.write_iter(jobs.iter().map(GpuLookupJob::from));
        });
        let job_buffer = gpu_jobs.finish(gpu);
        let size = (jobs.len() * 16) as u64;
        let answers = output(gpu, "lookup answers", size);
        let groups = jobs.len().div_ceil(WORKGROUP_SIZE as usize) as u32;
        let out: Vec<[f32; 4]> = checked(gpu, || {
            let buffers = [&level.beams, &level.depths, &job_buffer, &answers];
            let encoder = crate::buffers::dispatch(gpu, &self.pipeline, &buffers, groups);
            read_back(gpu, encoder, &answers, size)
        })?;
        Ok(Some(out.iter().map(|a| (Vec3::new(a[0], a[1], a[2]), a[3])).collect()))
    }
}

/// A tree level's beams as a lookup reads them (`lib/reproject.wgsl`): their rays
/// ([`GpuBeam::rays_only`], each on its region of `depths`), and per texel of their regions the
/// ray parameter of its nearest hit (−1 where it hits nothing; the texels past a region's
/// triangle, which no lookup reads, are left as they are).
pub struct LookupBeams {
    /// [`GpuBeam`]s.
    pub beams: wgpu::Buffer,
    /// Per texel, `f32`: `size²` a beam, row-major, in the beams' order.
    pub depths: wgpu::Buffer,
}

impl LookupBeams {
    /// `beams`, each on its region `(first texel, 0, size)` of `depths`, which the GPU wrote (a
    /// kept level's, [`super::GpuLevelPoints`]).
    pub fn on_regions<'b>(gpu: &Gpu, beams: impl Iterator<Item = (&'b Beam, [u32; 3])>, depths: wgpu::Buffer) -> Self {
        let mut gpu_beams: Vec<GpuBeam> = beams.map(|(beam, region)| GpuBeam::rays_only(beam, region)).collect();
        if gpu_beams.is_empty() {
            gpu_beams.push(GpuBeam::zeroed());
        }
        Self { beams: storage(gpu, "lookup beams", &gpu_beams, wgpu::BufferUsages::empty()), depths }
    }

    /// `beams` with their textures, uploaded (the depths written in place, in parallel); `None`
    /// where their texels or the beams do not fit one storage binding.
    pub fn upload(gpu: &Gpu, beams: &[(&Beam, &BeamTexture)]) -> Result<Option<Self>, GpuError> {
        // A beam's depths: size² whatever its list of hits holds.
        let square = |tex: &BeamTexture| (tex.size * tex.size) as usize;
        let texels: usize = beams.iter().map(|(_, t)| square(t)).sum();
        let limit = max_binding(gpu) as usize;
        if texels * 4 > limit || beams.len() * size_of::<GpuBeam>() > limit {
            return Ok(None);
        }
        let none = wgpu::BufferUsages::empty();
        let mut depths = Staged::<f32>::new(gpu, "lookup depths", texels.max(1), none);
        let squares = split_by_counts(depths.slots(), beams.iter().map(|(_, t)| square(t)))
            .ok_or(GpuError::Internal("lookup depths past their buffer"))?;
        squares.into_par_iter().zip(beams).for_each(|(Slots(out), (_, tex))| {
            let hits = tex.hits.iter().map(|h| h.map_or(-1.0, |h| h.t));
            out.write_iter(hits.chain(std::iter::repeat(-1.0)).take(square(tex)));
        });
        let regions = beams.iter().scan(0, |first, (beam, tex)| {
            let region = [*first as u32, 0, tex.size];
            *first += square(tex);
            Some((*beam, region))
        });
        Ok(Some(Self::on_regions(gpu, regions, depths.finish(gpu))))
    }
}
