//! glibc's allocator set for a frame loop. By default glibc maps every allocation above 128 KB
//! (its threshold rises with use, to at most 32 MB) straight from the kernel and returns it on
//! free, and trims the heap's top above 128 KB: each frame's rays, texels, records and staging
//! buffers (tens of megabytes) were then page-faulted and zeroed afresh, frame after frame.
//! Measured on lavapipe (facing mirrors, 1280×1024, 2 cores): a third of the calling thread's
//! samples were page faults, and the host ms per frame fell from 469 to about 270 once large
//! blocks stayed in the heap. The price: memory freed after a frame stays with the process, for
//! the next one.
#![allow(unsafe_code, reason = "glibc's mallopt is an FFI call (on Linux with glibc only, hence no expect)")]

/// Keep freed memory in the process: no allocation below 2 GB is mapped on its own, and the heap
/// is never trimmed. Call before other threads start.
pub(crate) fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets glibc's allocator parameters (both are documented ones, with
    // values in range); it is called at start-up, before any other thread allocates.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, i32::MAX);
        libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
    }
}
