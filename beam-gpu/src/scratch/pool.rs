//! The pool of scratch buffers a device keeps ([`ScratchPool`]) and the buffers it hands out
//! ([`Scratch`]), each handed back to it when dropped.

use std::ops::Deref;
use std::sync::{Arc, Mutex, PoisonError};

/// Smallest scratch buffer made; it makes powers of two.
const SCRATCH_MIN: u64 = 1 << 16;

/// Most buffers a pool keeps.
const SCRATCH_KEPT: usize = 64;

/// The scratch buffers a device's passes handed back ([`scratch`](crate::scratch::scratch)).
#[derive(Default)]
pub(crate) struct ScratchPool(Arc<Mutex<Vec<wgpu::Buffer>>>);

impl ScratchPool {
    /// A scratch buffer of at least `size` bytes made on `device` ([`scratch`](crate::scratch::scratch)).
    pub(super) fn take(&self, device: &wgpu::Device, label: &str, size: u64) -> Scratch {
        let pool = Arc::clone(&self.0);
        let mut kept = pool.lock().unwrap_or_else(PoisonError::into_inner);
        let fits = |b: &wgpu::Buffer| b.size() >= size && b.size() <= 2 * size.max(SCRATCH_MIN);
        let best = kept.iter().enumerate().filter(|(_, b)| fits(b)).min_by_key(|(_, b)| b.size()).map(|(i, _)| i);
        let buffer = match best {
            Some(i) => kept.swap_remove(i),
            None => device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(SCRATCH_MIN).next_power_of_two(),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        };
        drop(kept);
        Scratch { buffer: Some(buffer), pool }
    }
}

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
