//! Storage buffers written in place: the elements go straight into the queue's staging memory
//! (`Queue::write_buffer_with`), with no vector of them on the host and no copy of it. A level's
//! composite records alone are tens of megabytes a frame (facing mirrors at 1280×1024: 23.5 MB of
//! its 31 MB of uploads), which a vector first zeroed, then filled, then copied.
//!
//! This module holds the `unsafe` of it: the staging bytes seen as elements.
#![allow(unsafe_code, reason = "the one module of its crate that holds unsafe blocks, each with a SAFETY comment")]

use crate::Gpu;
use crate::buffers::storage;
use core::ptr::NonNull;
use std::time::{Duration, Instant};
use wgpu::WriteOnly;

/// A storage buffer (with `usage` besides) of `len` elements of `T` (whole four-byte words) being
/// written: its elements ([`Staged::slots`]) are the queue's staging memory, or a vector where the
/// device gives none aligned for `T`. [`Staged::finish`] hands the buffer over; an element left
/// unwritten is undefined. Several may be written at once (one pass filling several lists).
pub(crate) struct Staged<T> {
    buffer: wgpu::Buffer,
    view: Option<wgpu::QueueWriteBufferView>,
    /// The elements where there is no usable view.
    items: Vec<T>,
    len: usize,
    /// Host time spent making the buffer (the upload's, without the writing).
    took: Duration,
}

impl<T: bytemuck::Pod> Staged<T> {
    /// Start the buffer; for `len` 0, [`storage`]'s stand-in for an empty slice.
    pub(crate) fn new(gpu: &Gpu, label: &str, len: usize, usage: wgpu::BufferUsages) -> Self {
        const { assert!(size_of::<T>() % wgpu::COPY_BUFFER_ALIGNMENT as usize == 0) };
        let start = Instant::now();
        let bytes = (len * size_of::<T>()) as u64;
        let Some(size) = wgpu::BufferSize::new(bytes) else {
            let buffer = storage::<T>(gpu, label, &[], usage);
            return Self { buffer, view: None, items: Vec::new(), len, took: Duration::ZERO };
        };
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | usage,
            mapped_at_creation: false,
        });
        let view = gpu.queue.write_buffer_with(&buffer, 0, size);
        Self { buffer, view, items: Vec::new(), len, took: start.elapsed() }
    }

    /// The elements, to be written.
    pub(crate) fn slots(&mut self) -> WriteOnly<'_, [T]> {
        if self.view.as_mut().is_some_and(|v| elements::<T>(v.slice(..)).is_none()) {
            // Not aligned for `T`: dropped before anything else is written to the buffer, or its
            // unwritten bytes would be copied over the vector's.
            self.view = None;
        }
        match &mut self.view {
            // `elements` succeeded on this view above.
            Some(view) => elements::<T>(view.slice(..)).unwrap_or_default(),
            None => {
                self.items.resize(self.len, T::zeroed());
                WriteOnly::from_mut(&mut self.items[..])
            }
        }
    }

    /// The buffer, its elements on their way (with the next submission); counted as an upload of
    /// their bytes.
    pub(crate) fn finish(self, gpu: &Gpu) -> wgpu::Buffer {
        let Self { buffer, view, items, len, took } = self;
        if len == 0 {
            return buffer; // `storage` counted it
        }
        let start = Instant::now();
        match view {
            Some(view) => drop(view),
            None => gpu.queue.write_buffer(&buffer, 0, bytemuck::cast_slice(&items)),
        }
        gpu.record_upload(took + start.elapsed(), len * size_of::<T>());
        buffer
    }
}

/// `bytes` as write-only elements of `T`: `None` unless they are a whole number of `T`s and start
/// aligned for `T`.
fn elements<T: bytemuck::Pod>(mut bytes: WriteOnly<'_, [u8]>) -> Option<WriteOnly<'_, [T]>> {
    let (len, size) = (bytes.len(), size_of::<T>());
    let start = bytes.as_raw_element_ptr();
    if size == 0 || len % size != 0 || start.as_ptr().align_offset(align_of::<T>()) != 0 {
        return None;
    }
    // SAFETY: `start` begins the `len` bytes that `bytes` refers to, valid for writes and not
    // accessed otherwise while its lifetime lasts (`bytes` is consumed here, so the result takes
    // over its exclusive access for the same lifetime); it is aligned for `T` (checked above) and
    // `len / size` elements of `T` fill exactly those bytes. `WriteOnly` never reads, and every bit
    // pattern written is a valid `T` (`Pod`), as it is a valid run of bytes.
    Some(unsafe { WriteOnly::new(NonNull::slice_from_raw_parts(start.cast::<T>(), len / size)) })
}

/// A write-only slice that can go to another thread: what [`split_by_counts`] hands out, one per
/// piece of a parallel pass. (`WriteOnly` is `Send` for sized targets only.)
pub(crate) struct Slots<'a, T>(pub WriteOnly<'a, [T]>);

// SAFETY: a `WriteOnly<'a, [T]>` is an exclusive, write-only borrow of `T`s for `'a`, as a
// `&'a mut [T]` is, which is `Send` where `T` is: the thread it goes to is the only one that can
// write through it, and none reads.
unsafe impl<T: Send> Send for Slots<'_, T> {}

/// `all` split into consecutive write-only slices of `counts` elements each; `None` if the counts
/// add up to more than `all` holds.
pub(crate) fn split_by_counts<T>(
    mut all: WriteOnly<'_, [T]>,
    counts: impl IntoIterator<Item = usize>,
) -> Option<Vec<Slots<'_, T>>> {
    let mut out = Vec::new();
    for n in counts {
        let (head, tail) = all.split_at_checked(n).ok()?;
        out.push(Slots(head));
        all = tail;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_become_elements_only_whole_and_aligned() {
        let mut words = [0u32; 8];
        let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut words);
        assert!(elements::<u32>(WriteOnly::from_mut(&mut bytes[1..9])).is_none(), "misaligned");
        assert!(elements::<u32>(WriteOnly::from_mut(&mut bytes[..6])).is_none(), "not whole");
        let slots = elements::<u32>(WriteOnly::from_mut(&mut bytes[4..16])).unwrap();
        assert_eq!(slots.len(), 3);
        slots.write_iter([7, 8, 9]);
        assert_eq!(words, [0, 7, 8, 9, 0, 0, 0, 0]);
    }

    #[test]
    fn splits_in_order() {
        let mut v = [0u32; 6];
        let parts = split_by_counts(WriteOnly::from_mut(&mut v[..]), [2, 0, 3]).unwrap();
        for (k, Slots(part)) in parts.into_iter().enumerate() {
            let n = part.len();
            part.write_iter(std::iter::repeat_n(k as u32 + 1, n));
        }
        assert_eq!(v, [1, 1, 3, 3, 3, 0]);
        assert!(split_by_counts(WriteOnly::from_mut(&mut v[..]), [4, 3]).is_none());
    }
}
