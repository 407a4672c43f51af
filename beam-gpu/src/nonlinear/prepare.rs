//! Each beam's preparation for the atlas, kept from one frame's beam tree to the next: its bounds
//! (000 Algs. 3–4's per-beam quantities, a threshold-plane search each), its bounding-cone culling
//! by the BVH's boxes (000 App. A) and its record for the shaders. A beam is a function of the bits
//! it is made of (its base, boundary directions, parameterization and what it skips), and so is its
//! preparation: a beam of the next frame with the same bits (a camera that stands still or turns
//! about its position) takes the one made before, the same bits as making it again. A beam that
//! moved a little (an eye that moved) is prepared afresh but for its blocks: they are gathered
//! with its bounding cone widened, and a later frame's beam on the same face whose cone that
//! wider one holds takes them (a superset of its own, of which the GPU's tests of each triangle
//! against its own cone keep the same triangles). The GPU tests about a tenth more pairs for it,
//! still eye or not; gathering a face's first beam with its own cone instead made the frame where
//! the eye starts to move 50% slower on the host.

use super::beam::GpuBeam;
use beam_math::collide::{Cone, ConeSpheres};
use beam_math::glam::Vec3;
use beam_render::memo::FrameMemo;
use beam_render::nonlinear::{Beam, BeamJob, ConeCull, blocks_meeting, cone_cull};
use beam_scene::scene::Scene;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// How much wider than a beam's bounding cone its blocks are gathered: its half-angle by this
/// fraction of it (and a milliradian), its apex moved back by this fraction of its distance from
/// the base. A sixteenth adds about an eighth to the cone's cross-section.
const WIDEN: f32 = 1.0 / 16.0;

/// One beam made ready for the atlas.
pub(super) struct Prepared {
    /// How the GPU culls its triangles one by one.
    pub(super) cull: ConeCull,
    /// The blocks of the BVH's leaves whose boxes meet `gathered`.
    pub(super) blocks: Arc<[u32]>,
    /// Its record for the shaders, on no region yet.
    pub(super) beam: GpuBeam,
    /// The cone its blocks were gathered with, which holds its bounding cone.
    gathered: Cone,
}

impl Prepared {
    /// The preparation of `job`, its blocks those of the first of `near` (an earlier frame's
    /// preparations of beams on its face) whose gathering cone holds its bounding cone, if any
    /// (then `true`); else gathered with its cone widened.
    fn new(scene: &Scene, job: &BeamJob<'_>, near: &[Arc<Self>]) -> (Self, bool) {
        let tb = job.beam.texel_beam();
        let bounds = tb.s1_or_sn_bounds();
        let (cull, cone) = cone_cull(scene, tb, &bounds, job.exclude);
        let beam = GpuBeam::new(job.beam, &bounds, [0; 3], job.exclude);
        if let Some(p) = near.iter().find(|p| p.gathered.contains_cone(&cone)) {
            return (Self { cull, blocks: Arc::clone(&p.blocks), beam, gathered: p.gathered }, true);
        }
        let base = tb.base();
        let centroid = (base[0] + base[1] + base[2]) / 3.0;
        let wide = cone.widened(WIDEN * cone.angle + 1e-3, WIDEN * cone.apex.distance(centroid));
        // A cone past a right angle holds no other (`Cone::contains_cone`): no wider one then.
        let gathered = if wide.angle < core::f32::consts::FRAC_PI_2 { wide } else { cone };
        let blocks = blocks_meeting(scene, &ConeSpheres::new(&gathered)).into();
        (Self { cull, blocks, beam, gathered }, false)
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

/// A beam's face: the bits of its base.
type Face = [u32; 9];

fn face(job: &BeamJob<'_>) -> Face {
    let mut out = [0; 9];
    let floats = job.beam.texel_beam().base().into_iter().flat_map(|v| v.to_array());
    for (slot, x) in out.iter_mut().zip(floats) {
        *slot = x.to_bits();
    }
    out
}

/// The preparations of this frame's tree and of the last one's, by their beams' bits; and by
/// face, those the latest frame to make any on it made, for the next frames' beams that moved a
/// little.
#[derive(Default)]
pub(super) struct Preparations {
    exact: FrameMemo<Key, Arc<Prepared>>,
    /// By face: the latest frame that made preparations of beams on it, and those.
    made: FxHashMap<Face, (u64, Vec<Arc<Prepared>>)>,
    frame: u64,
    /// Beams prepared afresh that took the blocks of an earlier beam on their face, so far.
    blocks_reused: u64,
}

impl Preparations {
    /// A new frame begins: what the last frame did not ask for goes.
    pub(super) fn next_frame(&mut self) {
        self.exact.next_frame();
        self.frame += 1;
    }

    /// Beams found among the last frame's (and this one's) so far, and beams prepared afresh
    /// that took the blocks of an earlier beam on their face.
    pub(super) fn reused(&self) -> (u64, u64) {
        (self.exact.found(), self.blocks_reused)
    }
}

/// The preparation of each of `jobs`: with `memo`, found among this frame's and the last one's,
/// else made (in parallel, the blocks of an earlier frame's beam on its face taken where they
/// hold its own) and kept for the next frame; without, made afresh (beams outside a frame's tree,
/// such as the caustics' light beams, made once).
pub(super) fn prepared(scene: &Scene, jobs: &[BeamJob<'_>], memo: Option<&mut Preparations>) -> Vec<Arc<Prepared>> {
    let Some(memo) = memo else {
        return (0..jobs.len()).into_par_iter().map(|i| Arc::new(Prepared::new(scene, &jobs[i], &[]).0)).collect();
    };
    let Preparations { exact, made, frame, blocks_reused } = memo;
    // Which jobs were prepared afresh, marked where they are made (in parallel): kept by face
    // below, in the jobs' order.
    let taken = AtomicU64::new(0);
    let fresh: Vec<AtomicBool> = jobs.iter().map(|_| AtomicBool::new(false)).collect();
    let make = |i: usize| {
        let face = face(&jobs[i]);
        let near = made.get(&face).map_or(&[][..], |(_, p)| p.as_slice());
        let (prepared, took) = Prepared::new(scene, &jobs[i], near);
        taken.fetch_add(u64::from(took), Ordering::Relaxed);
        fresh[i].store(true, Ordering::Relaxed);
        Arc::new(prepared)
    };
    let out = exact.values(jobs.par_iter().map(key).collect(), make);
    *blocks_reused += taken.into_inner();
    for (i, _) in fresh.into_iter().enumerate().filter(|(_, f)| f.load(Ordering::Relaxed)) {
        let (face, p) = (face(&jobs[i]), Arc::clone(&out[i]));
        let (latest, on_face) = made.entry(face).or_insert((*frame, Vec::new()));
        if *latest != *frame {
            (*latest, *on_face) = (*frame, Vec::new());
        }
        on_face.push(p);
    }
    out
}
