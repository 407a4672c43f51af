//! Whitted paths past the beam tree followed depth first (`shaders/whitted.wgsl`'s `paths`): one
//! dispatch follows each point's paths through every bounce to their ends, which it appends, so
//! that a batch of jobs costs one submission and one wait for its counts rather than one per
//! bounce (seven on the glass lens). A dispatch's room for ends comes from the last dispatches'
//! ends per point; one that appended more is dispatched again with room for all it counted (the
//! radiance is only added to once the ends are shaded). The same ends as the waves', in another
//! order.

use super::whitted::{Ends, GpuWhitted, RestJob, RestPoints, WhittedCounts};
use crate::buffers::{buffer_entry, read_all, storage};
use crate::raytrace::RayTracer;
use crate::shade::ShadeInput;
use crate::{Gpu, GpuError};
use std::sync::atomic::Ordering;

/// Rounds of dispatches before the caller falls back to the waves: a dispatch that counted more
/// ends than it had room for goes again with room for them all, split where they would not fit
/// one shading.
const ROUNDS: usize = 4;

/// One depth-first dispatch: its job, its points (`count` of `buffer`'s [`ShadeInput`]s from
/// `offset` on, the first one's radiance at element `first` of the job's), its room for ends.
struct Item {
    job: usize,
    buffer: wgpu::Buffer,
    offset: usize,
    count: usize,
    first: usize,
    room: usize,
}

impl Item {
    /// This item in dispatches of at most `each` points (`align` dividing where one starts), each
    /// with room for its share of `ends` and a margin, at most `chunk`.
    fn split(self, each: usize, align: usize, ends: usize, chunk: usize) -> Vec<Self> {
        let each = each.max(align).next_multiple_of(align);
        (0..self.count)
            .step_by(each)
            .map(|from| {
                let count = each.min(self.count - from);
                let room = (ends as f64 * count as f64 / self.count.max(1) as f64 * 1.1).ceil() as usize + 64;
                Self {
                    buffer: self.buffer.clone(),
                    offset: self.offset + from,
                    first: self.first + from,
                    count,
                    room: room.min(chunk),
                    ..self
                }
            })
            .collect()
    }
}

impl GpuWhitted {
    /// The ends of the paths of `jobs`' points, each with its job, every point's paths followed
    /// depth first in one dispatch; `None` where they would not fit (the caller traces in waves).
    pub(super) fn depth_first(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        jobs: &[RestJob<'_>],
    ) -> Result<Option<Vec<(Ends, usize)>>, GpuError> {
        let chunk = Self::per_dispatch(gpu);
        // A dispatch's points start at a storage binding's offset alignment.
        let align = (gpu.device.limits().min_storage_buffer_offset_alignment as usize / size_of::<ShadeInput>()).max(1);
        let per_point = f64::from_bits(self.ends_per_point.load(Ordering::Relaxed));
        let mut items = Vec::new();
        for (job, j) in jobs.iter().enumerate() {
            let whole = match j.points {
                RestPoints::Host(points) => {
                    (storage(gpu, "whitted points", points, wgpu::BufferUsages::empty()), points.len())
                }
                RestPoints::Gpu(buffer, count) => (buffer.clone(), count),
            };
            let item = Item { job, buffer: whole.0, offset: 0, count: whole.1, first: j.first, room: 0 };
            // As many points a dispatch as the last ends per point let fit one shading.
            let expected = (whole.1 as f64 * per_point).ceil() as usize;
            let each = (chunk as f64 / per_point.max(1.0) / 1.1) as usize;
            items.extend(item.split(each.min(chunk), align, expected, chunk));
        }
        let (nodes, triangles) = tracer.buffers();
        let mut found = Vec::new();
        let mut most = 0.0f64;
        for _ in 0..ROUNDS {
            if items.is_empty() {
                break;
            }
            let (encoders, outs): (Vec<_>, Vec<_>) = items
                .iter()
                .map(|it| {
                    let bytes = |n: usize| (n * size_of::<ShadeInput>()) as u64;
                    let points = wgpu::BufferBinding {
                        buffer: &it.buffer,
                        offset: bytes(it.offset),
                        size: wgpu::BufferSize::new(bytes(it.count.max(1))),
                    };
                    let inputs = [
                        buffer_entry(0, nodes),
                        buffer_entry(1, triangles),
                        wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::Buffer(points) },
                    ];
                    let rooms = Some((1, it.room));
                    let (encoder, out) = self.dispatch(gpu, &self.paths, (it.count, it.first, false), &inputs, rooms);
                    (encoder.finish(), out)
                })
                .unzip();
            // One submission with the counts' copy.
            let counts = outs.iter().map(|o| (&o.counts, size_of::<WhittedCounts>() as u64));
            let counts: Vec<WhittedCounts> = read_all(gpu, encoders, counts)?;
            if let Some(c) = counts.iter().find(|c| c.overflow > 0) {
                return Err(GpuError::StackOverflow { ray: c.overflow as usize - 1 });
            }
            let mut again = Vec::new();
            for ((item, out), c) in items.into_iter().zip(outs).zip(counts) {
                let count = c.ends as usize;
                most = most.max(count as f64 / item.count.max(1) as f64);
                if count <= item.room {
                    if count > 0 {
                        found.push((Ends { inputs: out.ends, weights: out.weights, count: c.ends }, item.job));
                    }
                } else if item.count <= align {
                    // No fewer points a dispatch: more ends than one shading takes.
                    return Ok(None);
                } else {
                    // Room for every end it counted, in as many dispatches as they take.
                    let parts = count.div_ceil(chunk * 10 / 11).max(1);
                    let each = item.count.div_ceil(parts);
                    again.extend(item.split(each, align, count, chunk));
                }
            }
            items = again;
        }
        if !items.is_empty() {
            return Ok(None);
        }
        self.ends_per_point.store(most.to_bits(), Ordering::Relaxed);
        Ok(Some(found))
    }
}
