//! The calling thread's CPU time, for timing single-thread benchmark rows on a shared machine
//! (other processes' time slices do not count), and the CPU time of our own threads (the calling
//! thread and rayon's workers), for host work beside a software GPU whose threads share the cores.
//!
//! `clock_gettime(CLOCK_THREAD_CPUTIME_ID)` brings the thread's run time up to date when read;
//! `/proc/thread-self/schedstat`, which advances only at scheduler ticks (4 ms at 250 Hz), is too
//! coarse for the 30 ms a ray set takes.
#![allow(unsafe_code, reason = "the one module of its crate that holds unsafe blocks, each with a SAFETY comment")]

/// Seconds of CPU time the calling thread has used; `None` where the clock is not available.
#[cfg(unix)]
pub fn thread_cpu_seconds() -> Option<f64> {
    clock_seconds(libc::CLOCK_THREAD_CPUTIME_ID)
}

/// Seconds of CPU time the calling thread has used; `None` where the clock is not available.
#[cfg(not(unix))]
pub fn thread_cpu_seconds() -> Option<f64> {
    None
}

/// CPU seconds used so far by the calling thread and by the workers of rayon's pool (the threads
/// our host code runs on; a driver's own threads are not among them); `None` where the clocks are
/// not available (the workers' only on Linux). The workers' clocks are read from here, without
/// waking them or waiting for their work: cheap enough for every stage of a frame.
#[cfg(target_os = "linux")]
pub fn our_threads_cpu_seconds() -> Option<(f64, f64)> {
    let main = thread_cpu_seconds()?;
    let workers: Option<Vec<f64>> = worker_clocks()?.iter().map(|&id| clock_seconds(id)).collect();
    Some((main, workers?.iter().sum()))
}

/// The seconds clock `id` reads.
#[cfg(unix)]
fn clock_seconds(id: libc::clockid_t) -> Option<f64> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable `timespec`; `clock_gettime` writes only it and reports
    // failure (an unknown clock, such as a thread's that has exited) by its return value.
    let rc = unsafe { libc::clock_gettime(id, &mut ts) };
    (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

/// The CPU clocks of the workers of rayon's pool, asked of each worker once, by a broadcast on
/// the first call (rayon's global pool unless that call comes from inside another pool, whose
/// workers then stand for ours); `None` if a worker has none.
#[cfg(target_os = "linux")]
fn worker_clocks() -> Option<&'static [libc::clockid_t]> {
    static CLOCKS: std::sync::OnceLock<Option<Vec<libc::clockid_t>>> = std::sync::OnceLock::new();
    let clocks = CLOCKS.get_or_init(|| {
        rayon::broadcast(|_| {
            let mut id: libc::clockid_t = 0;
            // SAFETY: `pthread_self` names the calling thread, alive during the call; `id` is a
            // valid, writable `clockid_t`, which `pthread_getcpuclockid` writes only on success.
            let rc = unsafe { libc::pthread_getcpuclockid(libc::pthread_self(), &mut id) };
            (rc == 0).then_some(id)
        })
        .into_iter()
        .collect()
    });
    clocks.as_deref()
}

/// CPU seconds of our threads: not available off Linux.
#[cfg(not(target_os = "linux"))]
pub fn our_threads_cpu_seconds() -> Option<(f64, f64)> {
    None
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;
    use rayon::prelude::*;

    /// Work handed to rayon from outside its pool runs on the workers: their clocks advance.
    #[test]
    fn counts_the_work_of_rayon_workers() {
        let (main0, workers0) = our_threads_cpu_seconds().expect("thread clocks on Linux");
        let sum: f64 = (0..20_000_000u64).into_par_iter().map(|i| (i as f64).sqrt()).sum();
        std::hint::black_box(sum);
        let (main1, workers1) = our_threads_cpu_seconds().expect("thread clocks on Linux");
        assert!(workers1 > workers0 && main1 >= main0, "{workers0} -> {workers1}, {main0} -> {main1}");
    }
}
