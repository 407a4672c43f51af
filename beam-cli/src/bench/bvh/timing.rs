//! The benchmark's rays and how a tracer is timed on them.

use crate::bench::tracer::Tracer;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::cpu_clock::thread_cpu_seconds;
use rayon::prelude::*;
use std::time::Instant;

/// The rays of the benchmark.
pub(super) struct Rays {
    pub primary: Vec<Ray>,
    pub shadow: Vec<(Ray, f32)>,
    pub diffuse: Vec<Ray>,
    pub eye: Vec3,
    pub forward: Vec3,
}

/// How single-thread rows are timed.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Clock {
    /// Wall-clock time.
    Wall,
    /// The thread's own CPU time: on a shared machine other processes' time slices do not count.
    Thread,
}

/// Seconds `f` takes, by `clock`.
fn seconds(clock: Clock, f: impl FnOnce()) -> f64 {
    let (s, cpu) = (Instant::now(), thread_cpu_seconds());
    f();
    match (clock, cpu, thread_cpu_seconds()) {
        (Clock::Thread, Some(a), Some(b)) => b - a,
        _ => s.elapsed().as_secs_f64(),
    }
}

/// The ray kinds, in the order of the table.
pub(super) const KINDS: [&str; 3] = ["primary", "shadow", "diffuse"];

/// Mrays/s of one tracer on one ray kind with `threads` (1 by `clock`, or all by wall clock), from
/// one pass over the rays.
pub(super) fn throughput(t: &dyn Tracer, rays: &Rays, kind: &str, parallel: bool, clock: Clock) -> f64 {
    let sink = |x: bool| std::hint::black_box(x);
    let wall = Clock::Wall;
    let secs = match (kind, parallel) {
        ("shadow", false) => seconds(clock, || rays.shadow.iter().for_each(|(r, m)| _ = sink(t.occluded(r, *m)))),
        ("shadow", true) => {
            seconds(wall, || rays.shadow.par_iter().with_min_len(64).for_each(|(r, m)| _ = sink(t.occluded(r, *m))))
        }
        (_, false) => {
            let rs = if kind == "primary" { &rays.primary } else { &rays.diffuse };
            seconds(clock, || rs.iter().for_each(|r| _ = sink(t.closest(r).is_some())))
        }
        (_, true) => {
            let rs = if kind == "primary" { &rays.primary } else { &rays.diffuse };
            seconds(wall, || rs.par_iter().with_min_len(64).for_each(|r| _ = sink(t.closest(r).is_some())))
        }
    };
    let n = match kind {
        "primary" => rays.primary.len(),
        "shadow" => rays.shadow.len(),
        _ => rays.diffuse.len(),
    };
    n as f64 / secs / 1e6
}
