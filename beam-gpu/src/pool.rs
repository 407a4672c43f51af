//! The buffers a device keeps for reuse ([`BufferPool`]): the readbacks' mappable buffers and the
//! passes' scratch buffers. A frame asks for the sizes the last one asked for, so its buffers are
//! the last frame's memory: on a device whose memory is the host's (lavapipe) a fresh buffer's
//! pages are made on its first use and freed with it (most of the composite's host time, and 1–2 ms
//! a frame for a 10 MB image readback). The pool is a bounded lock-free queue: renderers on other
//! threads share the device, and no frame waits on a lock for a buffer.

use crossbeam_queue::ArrayQueue;

/// Buffers of one usage that were handed back, for the next buffer of about their size.
pub(crate) struct BufferPool {
    kept: ArrayQueue<wgpu::Buffer>,
    usage: wgpu::BufferUsages,
    /// Smallest buffer made; it makes powers of two.
    min: u64,
}

impl BufferPool {
    /// A pool of at most `capacity` buffers of `usage`, none smaller than `min` bytes.
    fn new(capacity: usize, usage: wgpu::BufferUsages, min: u64) -> Self {
        Self { kept: ArrayQueue::new(capacity), usage, min }
    }

    /// The pool of a device's mappable buffers (`MAP_READ | COPY_DST`) for readbacks
    /// ([`crate::buffers::readback`]): 8 at most, none under 64 KiB.
    pub(crate) fn readbacks() -> Self {
        Self::new(8, wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST, 1 << 16)
    }

    /// The pool of a device's scratch buffers (`STORAGE | COPY_SRC | COPY_DST`,
    /// [`crate::scratch::scratch`]): 64 at most, none under 64 KiB.
    pub(crate) fn scratch() -> Self {
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        Self::new(64, usage, 1 << 16)
    }

    /// A buffer of at least `size` bytes: one handed back at most twice as large (the first found),
    /// else a new one of the next power of two (at least `min`), made on `device`.
    pub(crate) fn take(&self, device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
        let fits = |b: &wgpu::Buffer| b.size() >= size && b.size() <= 2 * size.max(self.min);
        // Each kept buffer looked at once at most; those that do not fit go to the back.
        for _ in 0..self.kept.len() {
            match self.kept.pop() {
                Some(b) if fits(&b) => return b,
                Some(b) => self.give(b),
                None => break,
            }
        }
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size.max(self.min).next_power_of_two(),
            usage: self.usage,
            mapped_at_creation: false,
        })
    }

    /// Keep `buffer` for the next [`take`](Self::take); a full pool lets its oldest go.
    pub(crate) fn give(&self, buffer: wgpu::Buffer) {
        debug_assert_eq!(buffer.usage(), self.usage, "a buffer handed back to another usage's pool");
        drop(self.kept.force_push(buffer));
    }
}
