//! Where the GPU's nonlinear renderer spends its time ([`GpuTimes`]), summed over the renderer's
//! life by each stage that spends it ([`SummedTimes`], lock-free).

use std::sync::atomic::{AtomicU64, Ordering};

/// Where the GPU renderer spent its time, summed over calls.
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuTimes {
    /// Seconds in atlas passes: upload, draws and readback, waiting for the GPU.
    pub atlas_seconds: f64,
    /// Seconds on the CPU preparing them (beam quantities, bounding-cone culling, packing).
    pub prepare_seconds: f64,
    /// Seconds tracing rays on the GPU (the eye's view, the reference's Whitted rays).
    pub ray_seconds: f64,
    /// Seconds shading points (mirror and glass ones by Whitted rays past the tree) and compositing
    /// the beam tree on the GPU.
    pub shade_seconds: f64,
    /// Of the composite's, host seconds (not blocked on the device) following the Whitted rays of
    /// mirror and glass points past the tree's last level.
    pub whitted_host_seconds: f64,
    /// Atlas pages rendered.
    pub pages: u64,
    /// Beams drawn.
    pub beams: u64,
    /// Of them, beams whose preparation (bounds, culling by the BVH's boxes) the last frame's tree
    /// had made.
    pub beams_reused: u64,
    /// Of the others, beams whose blocks of the BVH an earlier frame's beam on their face had
    /// gathered, with a cone holding theirs.
    pub blocks_reused: u64,
    /// (beam, scene triangle) pairs on the pages: four per block of the BVH that the host kept
    /// for a beam, those the GPU culled included.
    pub triangles: u64,
    /// Beam trees composited on the GPU (the others fell back to the CPU's composite).
    pub gpu_composites: u64,
    /// Tree levels whose points were kept on the GPU ([`super::GpuLevelPoints`]).
    pub levels_kept: u64,
    /// Lookup jobs of points under coarse S-mesh faces in their child beams made on the GPU
    /// ([`super::GpuLookups`]): reflections and refractions.
    pub lookups: u64,
    /// Texels that tree levels handed to the host and the GPU composited too
    /// ([`super::GpuLevelPoints::records`]).
    pub level_records: u64,
    /// Points under coarse S-mesh faces (the eye's and the levels') whose composite records the
    /// GPU made, each looking its child beams up for its own scattered rays.
    pub coarse_records: u64,
    /// Beams rendered again on the host ([`beam_render::nonlinear::render_beam`]) because a texel's
    /// nearest hit on the GPU lay where a cut-out's surface is not there.
    pub cut_out_beams: u64,
    /// The GPU's own seconds in the atlas passes, by timestamp queries (all 0 where the device has
    /// none): bounding triangles, nearest hits (draws, or the compute pass), gather.
    pub atlas_pass_seconds: [f64; 3],
}

/// Seconds in a [`GpuTimes`], in [`SummedTimes`]' order.
const SECONDS: usize = 8;
/// Counts in a [`GpuTimes`], in [`SummedTimes`]' order.
const COUNTS: usize = 11;

impl GpuTimes {
    /// Its seconds, in [`SummedTimes`]' order.
    fn seconds(&self) -> [f64; SECONDS] {
        let [a, b, c] = self.atlas_pass_seconds;
        [
            self.atlas_seconds,
            self.prepare_seconds,
            self.ray_seconds,
            self.shade_seconds,
            self.whitted_host_seconds,
            a,
            b,
            c,
        ]
    }

    /// Its counts, in [`SummedTimes`]' order.
    fn counts(&self) -> [u64; COUNTS] {
        [
            self.pages,
            self.beams,
            self.beams_reused,
            self.blocks_reused,
            self.triangles,
            self.gpu_composites,
            self.levels_kept,
            self.lookups,
            self.level_records,
            self.coarse_records,
            self.cut_out_beams,
        ]
    }

    /// The times of `seconds` and `counts`, in [`SummedTimes`]' order.
    fn of(seconds: [f64; SECONDS], counts: [u64; COUNTS]) -> Self {
        let [atlas_seconds, prepare_seconds, ray_seconds, shade_seconds, whitted_host_seconds, a, b, c] = seconds;
        let [
            pages,
            beams,
            beams_reused,
            blocks_reused,
            triangles,
            gpu_composites,
            levels_kept,
            lookups,
            level_records,
            coarse_records,
            cut_out_beams,
        ] = counts;
        Self {
            atlas_seconds,
            prepare_seconds,
            ray_seconds,
            shade_seconds,
            whitted_host_seconds,
            pages,
            beams,
            beams_reused,
            blocks_reused,
            triangles,
            gpu_composites,
            levels_kept,
            lookups,
            level_records,
            coarse_records,
            cut_out_beams,
            atlas_pass_seconds: [a, b, c],
        }
    }

    /// The sum of these times and `other`.
    #[must_use]
    pub fn plus(&self, other: &Self) -> Self {
        let (s, o) = (self.seconds(), other.seconds());
        let (n, m) = (self.counts(), other.counts());
        Self::of(std::array::from_fn(|i| s[i] + o[i]), std::array::from_fn(|i| n[i] + m[i]))
    }
}

/// A stage's [`GpuTimes`] summed over the renderer's life (across frames), each field an atomic
/// (seconds as the bits of an `f64`): the stages add to it through `&self`, from any thread,
/// without a lock.
#[derive(Debug, Default)]
pub(super) struct SummedTimes {
    seconds: [AtomicU64; SECONDS],
    counts: [AtomicU64; COUNTS],
}

impl SummedTimes {
    /// Add what `f` adds to zero times.
    pub(super) fn add(&self, f: impl FnOnce(&mut GpuTimes)) {
        let mut delta = GpuTimes::default();
        f(&mut delta);
        for (sum, s) in self.seconds.iter().zip(delta.seconds()) {
            if s != 0.0 {
                // An f64 add on its bits: retried where another thread added in between.
                let add = |bits: u64| Some((f64::from_bits(bits) + s).to_bits());
                let _ = sum.fetch_update(Ordering::Relaxed, Ordering::Relaxed, add);
            }
        }
        for (sum, n) in self.counts.iter().zip(delta.counts()) {
            if n != 0 {
                sum.fetch_add(n, Ordering::Relaxed);
            }
        }
    }

    /// The times so far.
    pub(super) fn get(&self) -> GpuTimes {
        let seconds = std::array::from_fn(|i| f64::from_bits(self.seconds[i].load(Ordering::Relaxed)));
        GpuTimes::of(seconds, std::array::from_fn(|i| self.counts[i].load(Ordering::Relaxed)))
    }
}
