//! Each beam's preparation for the atlas, kept from one frame's beam tree to the next: its bounds
//! (000 Algs. 3–4's per-beam quantities, a threshold-plane search each), its bounding-cone culling
//! by the BVH's boxes (000 App. A) and its record for the shaders. A beam is a function of the bits
//! it is made of (its base, boundary directions, parameterization and what it skips), and so is its
//! preparation: a beam of the next frame with the same bits (a camera that stands still or turns
//! about its position) takes the one made before, the same bits as making it again.

use super::beam::GpuBeam;
use beam_math::glam::Vec3;
use beam_scene::memo::FrameMemo;
use beam_scene::nonlinear::{Beam, BeamJob, ConeCull, cone_blocks};
use beam_scene::scene::Scene;
use rayon::prelude::*;
use std::sync::Arc;

/// One beam made ready for the atlas.
pub(super) struct Prepared {
    /// How the GPU culls its triangles one by one.
    pub(super) cull: ConeCull,
    /// The blocks of the BVH's leaves whose boxes meet its bounding cone.
    pub(super) blocks: Vec<u32>,
    /// Its record for the shaders, on no region yet.
    pub(super) beam: GpuBeam,
}

impl Prepared {
    fn new(scene: &Scene, job: &BeamJob<'_>) -> Self {
        let tb = job.beam.texel_beam();
        let bounds = tb.s1_or_sn_bounds();
        let (cull, blocks) = cone_blocks(scene, tb, &bounds, job.exclude);
        Self { cull, blocks, beam: GpuBeam::new(job.beam, &bounds, [0; 3], job.exclude) }
    }
}

/// The bits a beam and what it skips are made of: base, boundary directions, the S3 vertex normals
/// or the bump's angle, the kind, and the skipped triangle and thickness (the rest of what a beam
/// skips follows from its face, which its base is).
type Key = [u32; 30];

fn key(job: &BeamJob<'_>) -> Key {
    let (kind, base, dirs, extra) = match job.beam {
        Beam::S1(b) => (1, b.base, b.dirs, [Vec3::ZERO; 3]),
        Beam::S3(b) => (3, b.base, b.dirs, b.interp.normals),
        Beam::Bumped(b) => {
            let s1 = &b.beam.beam;
            (2, s1.base, s1.dirs, [Vec3::new(b.beam.delta, b.bump.wavelength, 0.0), Vec3::ZERO, Vec3::ZERO])
        }
    };
    let mut out = [0; 30];
    let floats = base.iter().chain(&dirs).chain(&extra).flat_map(|v| v.to_array());
    for (slot, x) in out.iter_mut().zip(floats.chain([job.exclude.thickness])) {
        *slot = x.to_bits();
    }
    out[28] = kind;
    out[29] = job.exclude.prim;
    out
}

/// The preparations of this frame's tree and of the last one's.
pub(super) type Preparations = FrameMemo<Key, Arc<Prepared>>;

/// The preparation of each of `jobs`: with `memo`, found among this frame's and the last one's,
/// else made (in parallel) and kept for the next frame; without, made afresh (beams outside a
/// frame's tree, such as the caustics' light beams, made once).
pub(super) fn prepared(scene: &Scene, jobs: &[BeamJob<'_>], memo: Option<&mut Preparations>) -> Vec<Arc<Prepared>> {
    let make = |i: usize| Arc::new(Prepared::new(scene, &jobs[i]));
    match memo {
        Some(memo) => memo.values(jobs.par_iter().map(key).collect(), make),
        None => (0..jobs.len()).into_par_iter().map(make).collect(),
    }
}
