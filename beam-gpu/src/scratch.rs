//! Scratch buffers kept between passes and frames: the lists a pass appends to (the Whitted
//! waves' paths and ends, a level's points) were made and freed by the hundred a frame, 2.5 GB on
//! the glass lens at 1280×1024, and on a device whose memory is the host's (lavapipe) each made
//! and freed its pages on the host: most of the composite's host time. A [`Scratch`] goes back to
//! its device's pool when dropped (the device still orders the passes that used it before the
//! next that does), and the next scratch buffer of about its size reuses it.

use crate::Gpu;
use std::ops::Deref;
use std::sync::{Arc, Mutex, PoisonError};

/// Smallest scratch buffer made; it makes powers of two.
const SCRATCH_MIN: u64 = 1 << 16;

/// Most buffers a pool keeps.
const SCRATCH_KEPT: usize = 64;

/// The scratch buffers a device's passes handed back ([`scratch`]).
#[derive(Default)]
pub struct ScratchPool(Arc<Mutex<Vec<wgpu::Buffer>>>);

/// A storage buffer from a device's [`ScratchPool`], handed back to it when dropped. Hold it until
/// the work that uses it is submitted: dropped before, the next scratch buffer may be the same
/// memory, and the unsubmitted work would read what that one's work wrote.
pub struct Scratch {
    buffer: Option<wgpu::Buffer>,
    pool: Arc<Mutex<Vec<wgpu::Buffer>>>,
}

impl Deref for Scratch {
    type Target = wgpu::Buffer;

    fn deref(&self) -> &wgpu::Buffer {
        // Taken only by `drop`.
        self.buffer.as_ref().unwrap_or_else(|| unreachable!("a scratch buffer is held until dropped"))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let Some(buffer) = self.buffer.take() else { return };
        let mut kept = self.pool.lock().unwrap_or_else(PoisonError::into_inner);
        if kept.len() == SCRATCH_KEPT {
            // The smallest goes: it is the cheapest to make again.
            let smallest = kept.iter().enumerate().min_by_key(|(_, b)| b.size()).map(|(i, _)| i);
            smallest.map(|i| kept.swap_remove(i));
        }
        kept.push(buffer);
    }
}

/// A storage buffer (`STORAGE | COPY_SRC | COPY_DST`) of at least `size` bytes whose contents are
/// what an earlier pass left (not zeroed): for a list a pass appends to, read no further than the
/// count it appended. One an earlier scratch buffer handed back at most twice as large, else a new
/// one of the next power of two.
#[must_use]
pub fn scratch(gpu: &Gpu, label: &str, size: u64) -> Scratch {
    let pool = Arc::clone(&gpu.scratch.0);
    let mut kept = pool.lock().unwrap_or_else(PoisonError::into_inner);
    let fits = |b: &wgpu::Buffer| b.size() >= size && b.size() <= 2 * size.max(SCRATCH_MIN);
    let best = kept.iter().enumerate().filter(|(_, b)| fits(b)).min_by_key(|(_, b)| b.size()).map(|(i, _)| i);
    let buffer = match best {
        Some(i) => kept.swap_remove(i),
        None => gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size.max(SCRATCH_MIN).next_power_of_two(),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }),
    };
    drop(kept);
    Scratch { buffer: Some(buffer), pool }
}
