//! The WGSL nonlinear-beam functions run on batches of cases (`shaders/nonlinear_check.wgsl`), for
//! the conformance suite to compare with their CPU twins: `bounding_triangle` with beam-math's
//! [`NonlinearBeam::bounding_triangle`](beam_math::nonlinear::NonlinearBeam::bounding_triangle) and
//! [`BumpBeam::bounding_triangle`](beam_math::nonlinear::BumpBeam::bounding_triangle), `texel_ray`
//! with [`Beam::ray_at`], `lookup_project` (`lib/lookup.wgsl`) with [`Beam::project_in`] under
//! [`LOOKUP`](beam_render::nonlinear::LOOKUP).

use super::beam::GpuBeam;
use crate::buffers::{checked, compute_pipeline, dispatch, output, read_back, storage};
use crate::interface::{
    BOUNDING_BRUTE_FORCE, BOUNDING_GENERAL, BOUNDING_UNIQUE_PROJECTION, LOOKUP_CORNERS, LOOKUP_POLISHED, WORKGROUP_SIZE,
};
use crate::{Gpu, GpuError};
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_math::nonlinear::{BoundingCase, Projection};
use beam_render::nonlinear::{Beam, Exclude};
use bytemuck::{Pod, Zeroable};

/// One case: a scene triangle, a base point in `a`, or a point in `a` and a guess in `b` (`ω`, `t`);
/// the beam's index in `a[3]` (as bits).
///
/// WGSL twin: `CheckCase` in `shaders/nonlinear_check.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CheckCase {
    /// First vertex, or the base point; w: beam index bits.
    pub a: [f32; 4],
    /// Second vertex.
    pub b: [f32; 4],
    /// Third vertex.
    pub c: [f32; 4],
}

const _: () = assert!(size_of::<CheckCase>() == 48);

/// A bounding triangle computed by the shader: lower bounds and case (`None`: culled, behind the
/// base).
pub type GpuBoundingTriangle = Option<([f32; 3], BoundingCase)>;

/// How the shader found a lookup's projection ([`NonlinearCheck::lookups`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LookupFound {
    /// Polished by Newton's method (an S1 beam's needs none).
    Polished,
    /// Newton's method did not converge: the corner rays' S1 solution.
    Corners,
}

/// The compiled check pipelines.
pub struct NonlinearCheck {
    bounding: wgpu::ComputePipeline,
    rays: wgpu::ComputePipeline,
    lookups: wgpu::ComputePipeline,
}

impl NonlinearCheck {
    /// Compile both entry points.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(Self {
            bounding: compute_pipeline(gpu, "nonlinear_check", "check_bounding_triangles")?,
            rays: compute_pipeline(gpu, "nonlinear_check", "check_rays")?,
            lookups: compute_pipeline(gpu, "nonlinear_check", "check_lookups")?,
        })
    }

    fn run(
        &self,
        gpu: &Gpu,
        pipeline: &wgpu::ComputePipeline,
        beams: &[Beam],
        cases: &[CheckCase],
        per_case: usize,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        if cases.is_empty() {
            return Ok(Vec::new());
        }
        let groups = cases.len().div_ceil(WORKGROUP_SIZE as usize);
        if groups > 65_535 {
            return Err(GpuError::TooManyCases { cases: cases.len() });
        }
        let gpu_beams: Vec<GpuBeam> = beams
            .iter()
            .map(|b| GpuBeam::new(b, &b.texel_beam().s1_or_sn_bounds(), [0, 0, 1], Exclude::base(u32::MAX)))
            .collect();
        let beam_buffer = storage(gpu, "beams", &gpu_beams, wgpu::BufferUsages::empty());
        let case_buffer = storage(gpu, "cases", cases, wgpu::BufferUsages::empty());
        let size = (cases.len() * per_case * 16) as u64;
        let results = output(gpu, "results", size);
        checked(gpu, || {
            let encoder = dispatch(gpu, pipeline, &[&beam_buffer, &case_buffer, &results], groups as u32);
            read_back(gpu, encoder, &results, size)
        })
    }

    /// The shader's bounding triangle of each `(beam index, scene triangle)`.
    pub fn bounding_triangles(
        &self,
        gpu: &Gpu,
        beams: &[Beam],
        cases: &[(u32, Triangle)],
    ) -> Result<Vec<GpuBoundingTriangle>, GpuError> {
        let v = |p: Vec3, w: f32| [p.x, p.y, p.z, w];
        let cases: Vec<CheckCase> = cases
            .iter()
            .map(|(i, t)| CheckCase { a: v(t.v[0], f32::from_bits(*i)), b: v(t.v[1], 0.0), c: v(t.v[2], 0.0) })
            .collect();
        let out = self.run(gpu, &self.bounding, beams, &cases, 1)?;
        Ok(out
            .iter()
            .map(|r| {
                let case = match r[3] as u32 {
                    BOUNDING_BRUTE_FORCE => BoundingCase::BruteForce,
                    BOUNDING_GENERAL => BoundingCase::General,
                    BOUNDING_UNIQUE_PROJECTION => BoundingCase::UniqueProjection,
                    _ => return None,
                };
                Some(([r[0], r[1], r[2]], case))
            })
            .collect())
    }

    /// The shader's texel ray (origin, direction) of each `(beam index, base point)`.
    pub fn rays(&self, gpu: &Gpu, beams: &[Beam], cases: &[(u32, Vec3)]) -> Result<Vec<(Vec3, Vec3)>, GpuError> {
        let cases: Vec<CheckCase> = cases
            .iter()
            .map(|(i, w)| CheckCase { a: [w.x, w.y, w.z, f32::from_bits(*i)], b: [0.0; 4], c: [0.0; 4] })
            .collect();
        let out = self.run(gpu, &self.rays, beams, &cases, 2)?;
        Ok(out.chunks_exact(2).map(|p| (Vec3::from_slice(&p[0][..3]), Vec3::from_slice(&p[1][..3]))).collect())
    }

    /// The shader's lookup projection of each `(beam index, point, guess)`: `ω` and `t`, and how
    /// it was found; `None` where no corner-ray solution lies in front of the base.
    pub fn lookups(
        &self,
        gpu: &Gpu,
        beams: &[Beam],
        cases: &[(u32, Vec3, Projection)],
    ) -> Result<Vec<Option<(Projection, LookupFound)>>, GpuError> {
        let cases: Vec<CheckCase> = cases
            .iter()
            .map(|(i, q, g)| CheckCase {
                a: [q.x, q.y, q.z, f32::from_bits(*i)],
                b: [g.bary.x, g.bary.y, g.bary.z, g.t],
                c: [0.0; 4],
            })
            .collect();
        let out = self.run(gpu, &self.lookups, beams, &cases, 2)?;
        Ok(out
            .chunks_exact(2)
            .map(|r| {
                let found = match r[1][0] as u32 {
                    LOOKUP_POLISHED => LookupFound::Polished,
                    LOOKUP_CORNERS => LookupFound::Corners,
                    _ => return None,
                };
                Some((Projection { bary: Vec3::from_slice(&r[0][..3]), t: r[0][3] }, found))
            })
            .collect())
    }
}
