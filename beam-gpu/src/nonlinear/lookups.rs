//! The coarse S mesh's lookups on the GPU (`shaders/lookups.wgsl`): per point of a fine surface
//! under a coarse face (000 §7.1), where it reads a child beam for its own scattered ray, by
//! Newton's method on the beam's S^n rays and the texels' depths: beam-cpu's `reproject` in f32
//! (its projections checked by `gpu_lookup_projections_equal_cpu`, its images by
//! `gpu_coarse_smesh_equals_cpu`).

use super::beam::GpuBeam;
use crate::buffers::{checked, compute_pipeline, max_binding, output, read_back, storage};
use crate::interface::WORKGROUP_SIZE;
use crate::{Gpu, GpuError};
use beam_math::glam::Vec3;
use beam_scene::nonlinear::{Beam, BeamTexture, LookupJob};
use bytemuck::{Pod, Zeroable};

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

/// The compiled lookup pipeline.
pub struct GpuLookups {
    pipeline: wgpu::ComputePipeline,
}

impl GpuLookups {
    /// Compile `lookups.wgsl`.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(Self { pipeline: compute_pipeline(gpu, "lookups", "lookups")? })
    }

    /// Each job's coordinates on its beam's base and how far outside the base its last projection
    /// lay (beam-cpu's `reproject`), the beams `beams` with their textures; `None` where the beams'
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
        let texels: usize = beams.iter().map(|(_, t)| (t.size * t.size) as usize).sum();
        let limit = max_binding(gpu) as usize;
        if texels * 4 > limit || jobs.len() * 48 > limit || beams.len() * size_of::<GpuBeam>() > limit {
            return Ok(None);
        }
        let mut depths = Vec::with_capacity(texels);
        let gpu_beams: Vec<GpuBeam> = beams
            .iter()
            .map(|(beam, tex)| {
                let first = depths.len();
                depths.extend(tex.hits.iter().map(|h| h.map_or(-1.0, |h| h.t)));
                // size² texels a beam, whatever its list holds (none: every texel misses).
                depths.resize(first + (tex.size * tex.size) as usize, -1.0);
                let first = first as u32;
                GpuBeam::rays_only(beam, [first, 0, tex.size])
            })
            .collect();
        let gpu_jobs: Vec<GpuLookupJob> = jobs.iter().map(GpuLookupJob::from).collect();
        let beam_buffer = storage(gpu, "lookup beams", &gpu_beams, wgpu::BufferUsages::empty());
        let depth_buffer = storage(gpu, "lookup depths", &depths, wgpu::BufferUsages::empty());
        let job_buffer = storage(gpu, "lookup jobs", &gpu_jobs, wgpu::BufferUsages::empty());
        let size = (jobs.len() * 16) as u64;
        let answers = output(gpu, "lookup answers", size);
        let groups = jobs.len().div_ceil(WORKGROUP_SIZE as usize) as u32;
        let out: Vec<[f32; 4]> = checked(gpu, || {
            let buffers = [&beam_buffer, &depth_buffer, &job_buffer, &answers];
            let encoder = crate::buffers::dispatch(gpu, &self.pipeline, &buffers, groups);
            read_back(gpu, encoder, &answers, size)
        })?;
        Ok(Some(out.iter().map(|a| (Vec3::new(a[0], a[1], a[2]), a[3])).collect()))
    }
}
