//! The calling thread's CPU time, for timing single-thread benchmark rows on a shared machine
//! (other processes' time slices do not count), and the CPU time of our own threads (the calling
//! thread and rayon's workers), for host work beside a software GPU whose threads share the cores.
//!
//! `clock_gettime(CLOCK_THREAD_CPUTIME_ID)` brings the thread's run time up to date when read;
//! `/proc/thread-self/schedstat`, which advances only at scheduler ticks (4 ms at 250 Hz), is too
//! coarse for the 30 ms a ray set takes.
#![allow(unsafe_code)]

/// Seconds of CPU time the calling thread has used; `None` where the clock is not available.
#[cfg(unix)]
pub fn thread_cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable `timespec`; `clock_gettime` writes only it and reports
    // failure by its return value.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

/// Seconds of CPU time the calling thread has used; `None` where the clock is not available.
#[cfg(not(unix))]
pub fn thread_cpu_seconds() -> Option<f64> {
    None
}

/// CPU seconds used so far by the calling thread and by each worker of rayon's global pool (the
/// threads our host code runs on; a driver's own threads are not among them); `None` where the
/// clock is not available.
pub fn our_threads_cpu_seconds() -> Option<(f64, f64)> {
    let main = thread_cpu_seconds()?;
    let workers: Option<Vec<f64>> = rayon::broadcast(|_| thread_cpu_seconds()).into_iter().collect();
    Some((main, workers?.iter().sum()))
}
