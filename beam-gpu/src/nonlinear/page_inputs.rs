//! An atlas page's inputs on the GPU (`atlas.rs` packs the beams onto pages, `page.rs` renders
//! them): its beams on their regions, their (beam, block) pairs, how they cull their triangles,
//! their regions' first texels and the compute pass's jobs. They are a function of the page's
//! beams' preparations ([`Prepared`]) and of where the beams lie, so a page of the next frame with
//! the same preparations on the same regions (a camera that stands still) takes the buffers
//! uploaded before: 8.3 MB a frame on the glass lens, otherwise written again.

use super::beam::GpuBeam;
use super::cull::PageCulls;
use super::prepare::Prepared;
use crate::Gpu;
use crate::buffers::storage;
use crate::interface::WORKGROUP_SIZE;
use crate::staging::{Slots, Staged, split_by_counts};
use beam_render::memo::FrameMemo;
use beam_render::nonlinear::{BeamJob, region_texels};
use rayon::prelude::*;
use std::sync::Arc;

/// One page's inputs, uploaded.
pub(super) struct PageInputs {
    /// The preparations of its beams, kept so that the addresses in its key name them and no
    /// other while it is kept.
    _beams: Vec<Arc<Prepared>>,
    /// Its beams on their regions ([`GpuBeam`]s).
    pub beams: wgpu::Buffer,
    /// Per block a beam keeps: (its beam on the page, the block).
    pub blocks: wgpu::Buffer,
    /// Per beam: how it culls its triangles ([`super::BeamCull`]); the patches and rings they
    /// point into.
    pub culls: (wgpu::Buffer, wgpu::Buffer),
    /// Per beam, its first texel among the page's regions, then their total (`firsts`).
    pub first_texels: wgpu::Buffer,
    /// Where the nearest hits are found by compute: its jobs (a workgroup's run of a beam's texels
    /// against a run of its pairs) and how many.
    pub jobs: Option<(wgpu::Buffer, u32)>,
    /// Per beam, its pairs: four per block.
    pub ranges: Vec<(u32, u32)>,
    /// Per beam, its first texel among the page's regions, then their total.
    pub firsts: Vec<u32>,
    /// (beam, triangle) pairs on the page.
    pub pairs: usize,
}

/// A page as its inputs depend on it: per beam, the address of its preparation and its region
/// (x, y, side).
pub(super) type PageKey = Vec<(usize, [u32; 3])>;

/// The pages of this frame's tree and of the last one's.
pub(super) type PageMemo = FrameMemo<PageKey, Arc<PageInputs>>;

/// The key of a page whose beams are `prepared`, on `regions`.
pub(super) fn page_key(prepared: &[&Arc<Prepared>], regions: &[[u32; 3]]) -> PageKey {
    prepared.iter().map(|p| Arc::as_ptr(p) as usize).zip(regions.iter().copied()).collect()
}

impl PageInputs {
    /// Upload the page of `members` (indices into `jobs`, each prepared as `prepared[k]`, on
    /// `regions[k]`); with `job_pairs`, the compute pass's jobs of at most that many pairs.
    pub(super) fn new(
        gpu: &Gpu,
        jobs: &[BeamJob<'_>],
        members: &[usize],
        (prepared, regions): (&[&Arc<Prepared>], &[[u32; 3]]),
        job_pairs: Option<u32>,
    ) -> Self {
        let mut ranges = Vec::with_capacity(members.len());
        let mut firsts = Vec::with_capacity(members.len() + 1);
        let mut culls = PageCulls::default();
        firsts.push(0u32);
        let mut pairs = 0u32;
        for (k, (&i, p)) in members.iter().zip(prepared).enumerate() {
            culls.push(&p.cull, jobs[i].exclude);
            // The page's pairs fit one binding, so their count fits 32 bits; so do its texels.
            let n = 4 * p.blocks.len() as u32;
            ranges.push((pairs, pairs + n));
            pairs += n;
            firsts.push(firsts[k] + region_texels(jobs[i].size) as u32);
        }
        // The page's beams on their regions, written in place.
        let mut beams = Staged::<GpuBeam>::new(gpu, "beams", members.len(), wgpu::BufferUsages::empty());
        beams.slots().write_iter(prepared.iter().zip(regions).map(|(p, region)| {
            let mut beam = p.beam;
            beam.region[..3].copy_from_slice(region);
            beam
        }));
        // The (beam on the page, block) pairs, written in place, a beam's by a thread.
        let mut blocks = Staged::<[u32; 2]>::new(gpu, "blocks", pairs as usize / 4, wgpu::BufferUsages::empty());
        let parts = split_by_counts(blocks.slots(), prepared.iter().map(|p| p.blocks.len()));
        debug_assert!(parts.is_some(), "the blocks add up to the buffer's length");
        if let Some(parts) = parts {
            parts.into_par_iter().zip(prepared).enumerate().for_each(|(k, (Slots(out), p))| {
                out.write_iter(p.blocks.iter().map(|&block| [k as u32, block]));
            });
        }
        let jobs = job_pairs.map(|job_pairs| {
            // A job: a workgroup's run of a beam's texels against a run of its pairs.
            let mut list: Vec<[u32; 4]> = Vec::new();
            for (k, (&(start, end), w)) in ranges.iter().zip(firsts.windows(2)).enumerate() {
                for run in 0..(w[1] - w[0]).div_ceil(WORKGROUP_SIZE) {
                    for p in (start..end).step_by(job_pairs as usize) {
                        list.push([k as u32, run, p, end.min(p + job_pairs)]);
                    }
                }
            }
            (storage(gpu, "texel jobs", &list, wgpu::BufferUsages::empty()), list.len() as u32)
        });
        let none = wgpu::BufferUsages::empty();
        Self {
            _beams: prepared.iter().map(|&p| Arc::clone(p)).collect(),
            beams: beams.finish(gpu),
            blocks: blocks.finish(gpu),
            culls: (
                storage(gpu, "beam culls", &culls.culls, none),
                storage(gpu, "patches and rings", &culls.lists, none),
            ),
            first_texels: storage(gpu, "region firsts", &firsts, none),
            jobs,
            ranges,
            firsts,
            pairs: pairs as usize,
        }
    }
}
