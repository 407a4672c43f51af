//! Where a nonlinear frame's time goes, stage by stage: wall seconds and the host's share of them
//! (wall time less the seconds the backend blocked on its device), the split of 000 Table 2's last
//! column (CPU / GPU milliseconds per frame).

use beam_scene::nonlinear::BeamRenderer;
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
}

/// Laps a frame's stages against `renderer`'s device waits.
pub(super) struct StageClock<'r> {
    renderer: &'r dyn BeamRenderer,
    at: Instant,
    waited: f64,
    stages: Vec<Stage>,
}

impl<'r> StageClock<'r> {
    pub(super) fn start(renderer: &'r dyn BeamRenderer) -> Self {
        Self { renderer, at: Instant::now(), waited: renderer.waited_seconds(), stages: Vec::new() }
    }

    /// Close the stage that ran since the last lap as `name`.
    pub(super) fn lap(&mut self, name: &'static str) {
        let (at, waited) = (Instant::now(), self.renderer.waited_seconds());
        let seconds = (at - self.at).as_secs_f64();
        let host_seconds = (seconds - (waited - self.waited)).max(0.0);
        (self.at, self.waited) = (at, waited);
        match self.stages.iter_mut().find(|s| s.name == name) {
            Some(s) => {
                s.seconds += seconds;
                s.host_seconds += host_seconds;
            }
            None => self.stages.push(Stage { name, seconds, host_seconds }),
        }
    }

    pub(super) fn stages(self) -> Vec<Stage> {
        self.stages
    }
}
