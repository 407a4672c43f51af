//! Storage buffers written in place: the elements go straight into the queue's staging memory
//! (`Queue::write_buffer_with`), with no vector of them on the host and no copy of it. A level's
//! composite records alone are tens of megabytes a frame (facing mirrors at 1280×1024: 23.5 MB of
//! its 31 MB of uploads), which a vector first zeroed, then filled, then copied.
//!
//! This module holds the `unsafe` of it: the staging bytes seen as elements.
#![allow(unsafe_code)]

use crate::Gpu;
use crate::buffers::storage;
use core::ptr::NonNull;
use std::time::{Duration, Instant};
use wgpu::WriteOnly;

/// A storage buffer (with `usage` besides) of `len` elements of `T`, which `fill` writes, every
/// one, through the queue's staging memory; an element `fill` leaves unwritten is undefined.
/// Counted as an upload of its bytes (the time without `fill`'s). `len` 0 makes [`storage`]'s
/// stand-in for an empty slice.
pub fn storage_in_place<T: bytemuck::Pod>(
    gpu: &Gpu,
    label: &str,
    len: usize,
    usage: wgpu::BufferUsages,
    fill: impl FnOnce(WriteOnly<'_, [T]>),
) -> wgpu::Buffer {
    let bytes = (len * size_of::<T>()) as u64;
    let size = wgpu::BufferSize::new(bytes).filter(|_| bytes % wgpu::COPY_BUFFER_ALIGNMENT == 0);
    let Some(size) = size else {
        // Empty, or not whole words (no such element type here): through a vector.
        let mut items = vec![T::zeroed(); len];
        fill(WriteOnly::from_mut(&mut items[..]));
        return storage(gpu, label, &items, usage);
    };
    let start = Instant::now();
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | usage,
        mapped_at_creation: false,
    });
    let mut view = gpu.queue.write_buffer_with(&buffer, 0, size);
    let filling = match view.as_mut().and_then(|v| elements::<T>(v.slice(..))) {
        Some(slots) => {
            let f = Instant::now();
            fill(slots);
            f.elapsed()
        }
        None => {
            // No staging view, or one not aligned for `T`: through a vector (the view dropped
            // first, or its unwritten bytes would be copied over the vector's).
            drop(view.take());
            let mut items = vec![T::zeroed(); len];
            fill(WriteOnly::from_mut(&mut items[..]));
            gpu.queue.write_buffer(&buffer, 0, bytemuck::cast_slice(&items));
            Duration::ZERO
        }
    };
    drop(view);
    gpu.record_upload(start.elapsed().saturating_sub(filling), bytes as usize);
    buffer
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
pub struct Slots<'a, T>(pub WriteOnly<'a, [T]>);

// SAFETY: a `WriteOnly<'a, [T]>` is an exclusive, write-only borrow of `T`s for `'a`, as a
// `&'a mut [T]` is, which is `Send` where `T` is: the thread it goes to is the only one that can
// write through it, and none reads.
unsafe impl<T: Send> Send for Slots<'_, T> {}

/// `all` split into consecutive write-only slices of `counts` elements each; `None` if the counts
/// add up to more than `all` holds.
pub fn split_by_counts<T>(
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
