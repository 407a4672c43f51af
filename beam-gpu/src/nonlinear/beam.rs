//! The GPU layout of a nonlinear beam: the per-beam quantities of 000 Algs. 3–4 (extremal
//! directions, threshold plane, μ_b, μ_d, heights; θ2 and τ of eq. 5 for bump-mapped beams) computed
//! once by beam-math, and the Bernstein control points of eq. 1.

use beam_math::glam::Vec3;
use beam_math::nonlinear::{BeamBounds, Interpolant, NonlinearBeam};
use beam_render::nonlinear::{Beam, Exclude};
use bytemuck::{Pod, Zeroable};

/// Most control points of a GPU beam (S3: 10; [`crate::interface::MAX_CONTROL_POINTS`]).
pub const MAX_CONTROL_POINTS: usize = crate::interface::MAX_CONTROL_POINTS as usize;

/// A beam for the shaders.
///
/// WGSL twin: `Beam` in `shaders/shared/nonlinear.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuBeam {
    /// Base vertices `Pᵢ` (w unused).
    pub base: [[f32; 4]; 3],
    /// Unit boundary directions `dᵢ`.
    pub dirs: [[f32; 4]; 3],
    /// Extremal directions `d̂ᵢ` (000 §6.2).
    pub extremal: [[f32; 4]; 3],
    /// Inner unit normal of the base plane; w: the winding sign of the affine planes.
    pub normal: [f32; 4],
    /// Threshold plane `Π_T`: normal and offset.
    pub threshold: [f32; 4],
    /// Heights of the base; w: `t_max` of `Π_T`.
    pub heights: [f32; 4],
    /// `μ_b`, `μ_d` (eq. 4), bump angle `δ`, `τ = δ + φ` (eq. 5).
    pub offsets: [f32; 4],
    /// `θ2 = asin(min n·dᵢ)`, bump wavelength, lift (largest origin offset, for self-hits), unused.
    pub bump: [f32; 4],
    /// Atlas x, y, texels per side, excluded scene triangle (the base).
    pub region: [u32; 4],
    /// Degree `n`, control points, bumped (0 or 1), unused.
    pub kind: [u32; 4],
    /// Bernstein control points of `O(ω)`.
    pub origin: [[f32; 4]; MAX_CONTROL_POINTS],
    /// Bernstein control points of `d(ω)`.
    pub direction: [[f32; 4]; MAX_CONTROL_POINTS],
}

const _: () = assert!(size_of::<GpuBeam>() == 576);

fn v4(v: Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

impl GpuBeam {
    /// `beam` on an atlas region `(x, y, size)`, skipping scene triangle `exclude.prim` (a coarse
    /// S-mesh face's patch is culled by `shaders/beam_cull.wgsl`, which marks its ring per pair,
    /// [`crate::interface::PAIR_NEAR`]), its lift for self-hits at least the surface's thickness
    /// about a coarse face (as `beam_render::nonlinear::render_beam` takes it). `bounds` are the beam's [`s1_or_sn_bounds`](beam_render::nonlinear::TexelBeam::s1_or_sn_bounds) (for a bumped beam, its S1 beam's),
    /// which the caller has for bounding-cone culling.
    #[must_use]
    pub fn new(beam: &Beam, bounds: &BeamBounds, region: [u32; 3], exclude: Exclude<'_>) -> Self {
        let mut out = match beam {
            Beam::S1(b) => Self::from_beam(b, bounds),
            Beam::S3(b) => Self::from_beam(b, bounds),
            Beam::Bumped(b) => {
                let s1 = &b.beam.beam;
                let mut g = Self::from_beam(s1, bounds);
                let min_elevation = s1.dirs.iter().fold(1.0f32, |m, d| m.min(s1.normal.dot(*d)));
                g.offsets[2] = b.beam.delta;
                g.offsets[3] = b.beam.delta + b.beam.spread();
                g.bump = [min_elevation.clamp(-1.0, 1.0).asin(), b.bump.wavelength, 0.0, 0.0];
                g.kind[2] = 1;
                g
            }
        };
        out.bump[2] = out.bump[2].max(exclude.thickness);
        out.region = [region[0], region[1], region[2], exclude.prim];
        out
    }

    /// `beam`'s rays alone (base, boundary directions, control points; no bounds, which cost a
    /// threshold-plane search a beam) on a region `(first texel, 0, size)` of a texel list: what
    /// the lookups (`lib/reproject.wgsl`) read. A bumped beam takes its S1 beam's rays, marked
    /// bumped (`kind.z` 1: a lookup into it reads the face's own coordinates).
    #[must_use]
    pub fn rays_only(beam: &Beam, region: [u32; 3]) -> Self {
        fn of<L: Interpolant>(b: &NonlinearBeam<L>, region: [u32; 3]) -> GpuBeam {
            let p = &b.patch;
            let count = p.count.min(MAX_CONTROL_POINTS);
            let mut g = GpuBeam::zeroed();
            g.base = b.base.map(|v| v4(v, 0.0));
            g.dirs = b.dirs.map(|v| v4(v, 0.0));
            g.normal = v4(b.normal, b.winding());
            g.region = [region[0], region[1], region[2], u32::MAX];
            g.kind = [p.degree as u32, count as u32, 0, 0];
            for i in 0..count {
                g.origin[i] = v4(p.origin[i].as_vec3(), 0.0);
                g.direction[i] = v4(p.direction[i].as_vec3(), 0.0);
            }
            g
        }
        match beam {
            Beam::S1(b) => of(b, region),
            Beam::S3(b) => of(b, region),
            Beam::Bumped(b) => {
                let mut g = of(&b.beam.beam, region);
                g.kind[2] = 1;
                g
            }
        }
    }

    fn from_beam<L: Interpolant>(b: &NonlinearBeam<L>, bounds: &BeamBounds) -> Self {
        let p = &b.patch;
        let count = p.count.min(MAX_CONTROL_POINTS);
        let mut g = Self {
            base: b.base.map(|v| v4(v, 0.0)),
            dirs: b.dirs.map(|v| v4(v, 0.0)),
            extremal: bounds.extremal.map(|v| v4(v, 0.0)),
            normal: v4(b.normal, b.winding()),
            threshold: v4(bounds.threshold.plane.normal, bounds.threshold.plane.d),
            heights: v4(bounds.heights, bounds.threshold.t_max),
            offsets: [bounds.mu_b, bounds.mu_d, 0.0, 0.0],
            bump: [0.0, 0.0, bounds.mu_b, 0.0],
            region: [0; 4],
            kind: [p.degree as u32, count as u32, 0, 0],
            origin: [[0.0; 4]; MAX_CONTROL_POINTS],
            direction: [[0.0; 4]; MAX_CONTROL_POINTS],
        };
        for i in 0..count {
            g.origin[i] = v4(p.origin[i].as_vec3(), 0.0);
            g.direction[i] = v4(p.direction[i].as_vec3(), 0.0);
        }
        g
    }
}
