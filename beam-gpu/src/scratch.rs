//! Scratch buffers kept between passes and frames: the lists a pass appends to (the Whitted
//! waves' paths and ends, a level's points) were made and freed by the hundred a frame, 2.5 GB on
//! the glass lens at 1280×1024, and on a device whose memory is the host's (lavapipe) each made
//! and freed its pages on the host: most of the composite's host time. A [`Scratch`] goes back to
//! its device's pool when dropped (the device still orders the passes that used it before the
//! next that does), and the next scratch buffer of about its size reuses it.

use crate::device::Gpu;
use crate::pool::BufferPool;
use std::ops::Deref;
use std::sync::Arc;

/// A storage buffer (`STORAGE | COPY_SRC | COPY_DST`) of at least `size` bytes whose contents are
/// what an earlier pass left (not zeroed): for a list a pass appends to, read no further than the
/// count it appended. One an earlier scratch buffer handed back at most twice as large, else a new
/// one of the next power of two.
#[must_use]
pub(crate) fn scratch(gpu: &Gpu, label: &str, size: u64) -> Scratch {
    let pool = Arc::clone(&gpu.scratch);
    Scratch { buffer: Some(pool.take(&gpu.device, label, size)), pool }
}

/// A storage buffer from a device's scratch pool, handed back to it when dropped. Hold it until
/// the work that uses it is submitted: dropped before, the next scratch buffer may be the same
/// memory, and the unsubmitted work would read what that one's work wrote.
pub struct Scratch {
    buffer: Option<wgpu::Buffer>,
    pool: Arc<BufferPool>,
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
        if let Some(buffer) = self.buffer.take() {
            self.pool.give(buffer);
        }
    }
}
