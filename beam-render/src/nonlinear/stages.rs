//! Where a nonlinear frame's time goes, stage by stage: wall seconds, the host's share of them
//! (wall time less the seconds the backend blocked on its device), the split of 000 Table 2's last
//! column (CPU / GPU milliseconds per frame), and the CPU time of our own threads.

use crate::cpu_clock::our_threads_cpu_seconds;
use std::time::Instant;

/// One stage of a frame, summed over the times it ran (the beam tree's stages run once per level).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Stage {
    /// What it does.
    pub name: &'static str,
    /// Wall seconds.
    pub seconds: f64,
    /// Of them, seconds not blocked on the device: host work.
    pub host_seconds: f64,
    /// CPU seconds of our threads (the calling thread and rayon's workers, spin-waits included)
    /// meanwhile: host work that a software GPU's threads, sharing the cores, do not inflate as
    /// they inflate `host_seconds`. 0 where the clocks are not available (off Linux). A lap
    /// reads one clock per thread, a system call each.
    pub cpu_seconds: f64,
}

/// Laps a frame's stages against the seconds its renderer has blocked on its device
/// ([`super::DeviceWaits::waited_seconds`], read at each lap).
pub(super) struct StageClock {
    at: Instant,
    waited: f64,
    cpu: Option<f64>,
    stages: Vec<Stage>,
}

/// CPU seconds of the calling thread and rayon's workers together.
fn cpu_now() -> Option<f64> {
    our_threads_cpu_seconds().map(|(main, workers)| main + workers)
}

impl StageClock {
    /// A clock started with the renderer's device waits so far, `waited` seconds.
    pub(super) fn start(waited: f64) -> Self {
        Self { at: Instant::now(), waited, cpu: cpu_now(), stages: Vec::new() }
    }

    /// Close the stage that ran since the last lap as `name`, the renderer's device waits so far
    /// `waited` seconds.
    pub(super) fn lap(&mut self, name: &'static str, waited: f64) {
        let (at, cpu) = (Instant::now(), cpu_now());
        let seconds = (at - self.at).as_secs_f64();
        let host_seconds = (seconds - (waited - self.waited)).max(0.0);
        let cpu_seconds = cpu.zip(self.cpu).map_or(0.0, |(now, then)| (now - then).max(0.0));
        (self.at, self.waited, self.cpu) = (at, waited, cpu);
        match self.stages.iter_mut().find(|s| s.name == name) {
            Some(s) => {
                s.seconds += seconds;
                s.host_seconds += host_seconds;
                s.cpu_seconds += cpu_seconds;
            }
            None => self.stages.push(Stage { name, seconds, host_seconds, cpu_seconds }),
        }
    }

    pub(super) fn stages(self) -> Vec<Stage> {
        self.stages
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stage that computes on the calling thread reports CPU time, and no more than the CPU
    /// time all our threads used meanwhile (the workers' clocks are read, not asked, so other
    /// tests' rayon work cannot hold a lap up); one that only waits reports wall time.
    #[test]
    fn laps_count_the_cpu_time_of_our_threads() {
        let mut clock = StageClock::start(0.0);
        let before = our_threads_cpu_seconds();
        let mut x = 1.0f64;
        for i in 0..20_000_000u64 {
            x = (x * 1.000_000_1 + i as f64).sqrt();
        }
        std::hint::black_box(x);
        clock.lap("compute", 0.0);
        let all = before.zip(our_threads_cpu_seconds()).map(|((m0, w0), (m1, w1))| m1 - m0 + w1 - w0);
        std::thread::sleep(std::time::Duration::from_millis(20));
        clock.lap("wait", 0.0);
        let stages = clock.stages();
        let (compute, wait) = (&stages[0], &stages[1]);
        if our_threads_cpu_seconds().is_some() {
            assert!(compute.cpu_seconds > 0.0, "{compute:?}");
            assert!(compute.cpu_seconds <= all.unwrap() + 1e-3, "{compute:?} vs {all:?}");
        } else {
            assert_eq!(compute.cpu_seconds, 0.0);
        }
        assert!(wait.seconds >= 0.02 && wait.host_seconds >= 0.02, "{wait:?}");
    }
}
