//! Shadings submitted without waiting ([`crate::shade::PointShader::shade_inputs`] inside
//! [`crate::shade::PointShader::shade_checked`]): each encodes as many passes as the last frame's
//! shadings needed and copies out how many points each pass left unfinished; the frame reads every
//! shading's counts back once, at its end, rather than once per shading. Where a shading was left
//! unfinished, the frame is shaded again with shadings that wait for their own counts.

use crate::buffers::read_all;
use crate::{Gpu, GpuError};

/// The shadings of one frame: whether they wait for their own counts, and the passes they needed.
/// A value of the frame's shading, lent to each shading in turn.
#[derive(Debug)]
pub struct ShadeChecks {
    wait: bool,
    /// Per shading submitted unchecked: where its passes' counts of unfinished points lie, and how
    /// many passes it encoded.
    pending: Vec<(wgpu::Buffer, u32)>,
    /// The most passes a shading that waited needed.
    most: u32,
}

impl ShadeChecks {
    /// Shadings that submit their passes and go on, checked together at the frame's end.
    #[must_use]
    pub(crate) fn unchecked() -> Self {
        Self { wait: false, pending: Vec::new(), most: 1 }
    }

    /// Shadings that wait for their counts after each submission, until their points are done.
    #[must_use]
    pub(crate) fn waiting() -> Self {
        Self { wait: true, ..Self::unchecked() }
    }

    /// Whether shadings wait for their own counts.
    pub(crate) fn wait(&self) -> bool {
        self.wait
    }

    /// Note a shading submitted with `passes` passes, each pass's count of unfinished points (a
    /// `u32`) in `left` after the last.
    pub(crate) fn add(&mut self, left: wgpu::Buffer, passes: u32) {
        self.pending.push((left, passes));
    }

    /// Note a shading that waited and needed `passes` passes.
    pub(crate) fn waited(&mut self, passes: u32) {
        self.most = self.most.max(passes);
    }

    /// Read back the counts of every shading submitted unchecked in one wait. Returns the passes
    /// the most demanding shading needed, or `None` where one still had points unfinished after
    /// its last pass (its radiance is incomplete).
    pub(crate) fn needed(&mut self, gpu: &Gpu) -> Result<Option<u32>, GpuError> {
        let pending = std::mem::take(&mut self.pending);
        let mut most = self.most;
        if pending.is_empty() {
            return Ok(Some(most));
        }
        let left: Vec<u32> = read_all(gpu, Vec::new(), pending.iter().map(|(b, n)| (b, 4 * u64::from(*n))))?;
        let mut rest = &left[..];
        for (_, passes) in &pending {
            let (counts, after) = rest.split_at((*passes as usize).min(rest.len()));
            rest = after;
            match counts.iter().position(|&n| n == 0) {
                Some(k) => most = most.max(k as u32 + 1),
                None => return Ok(None),
            }
        }
        Ok(Some(most))
    }
}
