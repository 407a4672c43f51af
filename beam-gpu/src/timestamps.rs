//! The GPU's own time in a few passes of one submission, by timestamp queries at each pass's
//! beginning and end, where the device has them (`wgpu::Features::TIMESTAMP_QUERY`, which
//! [`crate::Gpu::new`] asks for when the adapter offers it). Resolved into the caller's readback,
//! so timing a submission costs no wait of its own.

use crate::Gpu;

/// Timestamp queries for `passes` passes: pass `i` writes queries `2i` (beginning) and `2i + 1`
/// (end).
pub(crate) struct PassTimer {
    set: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    passes: u32,
}

impl PassTimer {
    /// Queries for `passes` passes, or `None` where the device has no timestamp queries.
    #[must_use]
    pub(crate) fn new(gpu: &Gpu, passes: u32) -> Option<Self> {
        if !gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) || passes == 0 {
            return None;
        }
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: 2 * passes,
        });
        let resolved = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass timestamps"),
            size: 16 * u64::from(passes),
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Some(Self { set, resolved, passes })
    }

    /// Bytes the timestamps take in a readback: two `u64` per pass.
    #[must_use]
    pub(crate) fn bytes(&self) -> u64 {
        16 * u64::from(self.passes)
    }

    /// What compute pass `i` writes.
    #[must_use]
    pub(crate) fn compute(&self, i: u32) -> wgpu::ComputePassTimestampWrites<'_> {
        debug_assert!(i < self.passes);
        wgpu::ComputePassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(2 * i),
            end_of_pass_write_index: Some(2 * i + 1),
        }
    }

    /// What render pass `i` writes.
    #[must_use]
    pub(crate) fn render(&self, i: u32) -> wgpu::RenderPassTimestampWrites<'_> {
        debug_assert!(i < self.passes);
        wgpu::RenderPassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(2 * i),
            end_of_pass_write_index: Some(2 * i + 1),
        }
    }

    /// Resolve the queries and copy them into `readback` at `offset` (a multiple of 4), after every
    /// timed pass of `encoder`.
    pub(crate) fn copy_to(&self, encoder: &mut wgpu::CommandEncoder, readback: &wgpu::Buffer, offset: u64) {
        encoder.resolve_query_set(&self.set, 0..2 * self.passes, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, readback, offset, self.bytes());
    }

    /// Seconds in each pass from the `bytes` copied by [`Self::copy_to`] (0 for a pass whose end
    /// reads before its beginning, as a device may report after a clock change).
    #[must_use]
    pub(crate) fn seconds(gpu: &Gpu, bytes: &[u8]) -> Vec<f64> {
        let period = f64::from(gpu.queue.get_timestamp_period()) * 1e-9;
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(bytes);
        ticks.chunks_exact(2).map(|t| t[1].saturating_sub(t[0]) as f64 * period).collect()
    }
}

/// Submit `encoder` and read back the first `size` bytes of `source` as `T`s, with, where `timer`
/// is given, the seconds of its passes (summed) resolved into the same readback: one wait.
pub(crate) fn read_back_timed<T: bytemuck::Pod>(
    gpu: &Gpu,
    mut encoder: wgpu::CommandEncoder,
    source: &wgpu::Buffer,
    size: u64,
    timer: Option<&PassTimer>,
) -> Result<(Vec<T>, Option<f64>), crate::GpuError> {
    let Some(timer) = timer else {
        return Ok((crate::buffers::read_back(gpu, encoder, source, size)?, None));
    };
    let into = crate::buffers::readback(gpu, size + timer.bytes());
    encoder.copy_buffer_to_buffer(source, 0, into.buffer(), 0, size);
    timer.copy_to(&mut encoder, into.buffer(), size);
    gpu.submit([encoder.finish()]);
    crate::buffers::map_with(gpu, into, |bytes| {
        let (items, stamps) = bytes.split_at(size as usize);
        (bytemuck::pod_collect_to_vec(items), Some(PassTimer::seconds(gpu, stamps).iter().sum()))
    })
}
