//! Buffer upload, compute dispatch and readback shared by the pipelines.

use crate::{Gpu, GpuError};
use std::time::Instant;
use wgpu::util::DeviceExt;

/// A storage buffer holding `items`; when there are none, zeros the size of one `T` (at least 64
/// bytes): wgpu refuses empty buffers, and a binding must hold at least one element of the
/// shader's array (`T` is its Rust twin), so a smaller pad fails validation.
#[must_use]
pub fn storage<T: bytemuck::Pod>(gpu: &Gpu, label: &str, items: &[T], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    let padded = vec![0u8; empty_size::<T>()];
    let contents = if items.is_empty() { &padded[..] } else { bytemuck::cast_slice(items) };
    let start = Instant::now();
    let usage = wgpu::BufferUsages::STORAGE | usage;
    // Written through the queue's staging buffer: a buffer mapped at creation is zeroed by wgpu
    // before the contents are copied in (on lavapipe, as long as the copy). `write_buffer` takes
    // whole four-byte words.
    let buffer = if contents.len() % wgpu::COPY_BUFFER_ALIGNMENT as usize == 0 {
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: contents.len() as u64,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue.write_buffer(&buffer, 0, contents);
        buffer
    } else {
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    };
    gpu.record_upload(start.elapsed(), contents.len());
    buffer
}

/// `queue.write_buffer` of `data` into `buffer` at `offset`, counted as an upload.
pub fn write(gpu: &Gpu, buffer: &wgpu::Buffer, offset: u64, data: &[u8]) {
    let start = Instant::now();
    gpu.queue.write_buffer(buffer, offset, data);
    gpu.record_upload(start.elapsed(), data.len());
}

/// Bytes of the zeroed stand-in [`storage`] uploads for an empty slice of `T`: one element, at
/// least 64 bytes.
#[must_use]
pub const fn empty_size<T>() -> usize {
    let one = size_of::<T>();
    if one > 64 { one } else { 64 }
}

/// The largest buffer one storage binding of the device takes.
#[must_use]
pub fn max_binding(gpu: &Gpu) -> u64 {
    let limits = gpu.device.limits();
    limits.max_storage_buffer_binding_size.min(limits.max_buffer_size)
}

/// A uniform buffer holding `bytes`.
#[must_use]
pub fn uniform(gpu: &Gpu, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    let start = Instant::now();
    let buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    });
    gpu.record_upload(start.elapsed(), bytes.len());
    buffer
}

/// Submit `encoder` after copying `size` bytes of `source` into a mappable buffer, wait, and read
/// them back as `T`s (copied once, from where they are mapped).
pub fn read_back<T: bytemuck::Pod>(
    gpu: &Gpu,
    mut encoder: wgpu::CommandEncoder,
    source: &wgpu::Buffer,
    size: u64,
) -> Result<Vec<T>, GpuError> {
    let readback = readback(gpu, size);
    encoder.copy_buffer_to_buffer(source, 0, readback.buffer(), 0, size);
    gpu.submit([encoder.finish()]);
    map_with(gpu, readback, bytemuck::pod_collect_to_vec)
}

/// The first `bytes` of each buffer, read back in one copy and one wait after the work `first`,
/// as `T`s.
pub fn read_all<'a, T: bytemuck::Pod>(
    gpu: &Gpu,
    first: Vec<wgpu::CommandBuffer>,
    sources: impl Iterator<Item = (&'a wgpu::Buffer, u64)>,
) -> Result<Vec<T>, GpuError> {
    map_all(gpu, first, sources, bytemuck::pod_collect_to_vec)
}

/// As [`read_all`], but `read` is handed the bytes where they are mapped (one after another, none
/// where there are none) instead of a copy.
pub fn map_all<'a, T>(
    gpu: &Gpu,
    first: Vec<wgpu::CommandBuffer>,
    sources: impl Iterator<Item = (&'a wgpu::Buffer, u64)>,
    read: impl FnOnce(&[u8]) -> T,
) -> Result<T, GpuError> {
    let sources: Vec<_> = sources.filter(|(_, bytes)| *bytes > 0).collect();
    let total: u64 = sources.iter().map(|(_, bytes)| bytes).sum();
    if total == 0 {
        gpu.submit(first);
        return Ok(read(&[]));
    }
    let readback = readback(gpu, total);
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    let mut at = 0;
    for (source, bytes) in sources {
        encoder.copy_buffer_to_buffer(source, 0, readback.buffer(), at, bytes);
        at += bytes;
    }
    gpu.submit(first.into_iter().chain([encoder.finish()]));
    map_with(gpu, readback, read)
}

/// A mappable buffer for a readback of `size` bytes ([`readback`]), used once by [`map_with`].
pub struct Readback {
    buffer: wgpu::Buffer,
    size: u64,
}

impl Readback {
    /// The buffer to copy into (its first `size` bytes are read).
    #[must_use]
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}

/// A mappable buffer (`MAP_READ | COPY_DST`) for `size` bytes: one an earlier readback handed back
/// ([`map_with`]) at most twice as large, else a new one of the next power of two. A frame reads
/// back the same sizes as the last one (the image, the atlas pages' hits), so its readbacks reuse
/// the last frame's memory (the device's pool, `pool.rs`).
#[must_use]
pub fn readback(gpu: &Gpu, size: u64) -> Readback {
    Readback { buffer: gpu.readbacks.take(&gpu.device, "readback", size), size }
}

/// How long [`wait`] keeps waiting on a queue that reports timeouts, in seconds.
const WAIT_SECONDS: u64 = 600;

/// Wait until the queue's work is done. wgpu waits on the fence with no timeout (`u64::MAX` ns),
/// yet lavapipe under load has answered such a wait with a timeout while the work was still
/// running (the glossy gather on a 2-core host); such a wait is made again, for up to
/// [`WAIT_SECONDS`] in all, so that a slow device is waited for and a hung one still fails.
fn wait(gpu: &Gpu) -> Result<(), GpuError> {
    let start = Instant::now();
    loop {
        match gpu.device.poll(wgpu::PollType::wait_indefinitely()) {
            Err(wgpu::PollError::Timeout) if start.elapsed().as_secs() < WAIT_SECONDS => {}
            done => return done.map(drop).map_err(GpuError::Wait),
        }
    }
}

/// Wait for the queue and hand `read` the bytes of `readback` where they are mapped (no copy: a
/// large readback is unpacked straight from them); the buffer goes back to the device for the
/// next readbacks ([`readback`]). Mapped ranges start at an 8-byte boundary (`wgpu::MAP_ALIGNMENT`).
pub fn map_with<T>(gpu: &Gpu, readback: Readback, read: impl FnOnce(&[u8]) -> T) -> Result<T, GpuError> {
    let Readback { buffer, size } = readback;
    // Mapped in whole four-byte words.
    let slice = buffer.slice(..size.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT).min(buffer.size()));
    slice.map_async(wgpu::MapMode::Read, |_| {});
    let start = Instant::now();
    wait(gpu)?;
    let (waited, start) = (start.elapsed(), Instant::now());
    let data = slice.get_mapped_range().map_err(GpuError::Readback)?;
    let bytes = &data[..(size as usize).min(data.len())];
    let (out, len) = (read(bytes), bytes.len());
    drop(data);
    buffer.unmap();
    gpu.record(waited, len, start.elapsed());
    gpu.readbacks.give(buffer);
    Ok(out)
}

/// A shader module of [`crate::shaders`] (its shared code prepended), compiled by the device.
pub fn shader_module(gpu: &Gpu, shader: &str) -> Result<wgpu::ShaderModule, GpuError> {
    let source = crate::shaders::source(shader).ok_or_else(|| GpuError::NoShader { name: shader.to_string() })?;
    Ok(gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(shader),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    }))
}

/// The compute pipeline of entry point `entry` of shader `shader`, bindings laid out by the shader.
pub fn compute_pipeline(gpu: &Gpu, shader: &str, entry: &str) -> Result<wgpu::ComputePipeline, GpuError> {
    let module = shader_module(gpu, shader)?;
    Ok(gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    }))
}

/// An encoder with one dispatch of `groups` workgroups of `pipeline`, `buffers` bound in order at
/// group 0 (binding `i` the `i`-th) ([`compute_pass`]).
#[must_use]
pub fn dispatch(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    buffers: &[&wgpu::Buffer],
    groups: u32,
) -> wgpu::CommandEncoder {
    let entries: Vec<_> = buffers.iter().zip(0..).map(|(b, i)| buffer_entry(i, b)).collect();
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    compute_pass(&mut encoder, pipeline, &bind, groups);
    encoder
}

/// A pass of `groups` workgroups of `pipeline`, `bind` at group 0, added to `encoder`; past 65,535
/// groups the dispatch is `65,535 × ⌈groups / 65,535⌉` (the shader folds `y` into its index, see
/// [`crate::interface::WORKGROUP_SIZE`]).
pub fn compute_pass(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    bind: &wgpu::BindGroup,
    groups: u32,
) {
    compute_pass_timed(encoder, pipeline, bind, groups, None);
}

/// [`compute_pass`], its beginning and end written to timestamp queries where `timestamps` says.
pub fn compute_pass_timed(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    bind: &wgpu::BindGroup,
    groups: u32,
    timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
) {
    let mut pass =
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: timestamps });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind, &[]);
    pass.dispatch_workgroups(groups.min(65_535), groups.div_ceil(65_535), 1);
}

/// A pass of `pipeline` over `count` invocations (of [`crate::interface::WORKGROUP_SIZE`] a
/// workgroup) with `entries` bound at group 0, added to `encoder` ([`compute_pass`]); none for none.
pub fn encode_pass(
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    count: u32,
    entries: &[wgpu::BindGroupEntry<'_>],
) {
    encode_pass_timed(gpu, encoder, pipeline, count, entries, None);
}

/// [`encode_pass`], its beginning and end written to timestamp queries where `timestamps` says.
pub fn encode_pass_timed(
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    count: u32,
    entries: &[wgpu::BindGroupEntry<'_>],
    timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
) {
    if count == 0 {
        return;
    }
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries,
    });
    compute_pass_timed(encoder, pipeline, &bind, count.div_ceil(crate::interface::WORKGROUP_SIZE), timestamps);
}

/// Binding `binding`: all of buffer `b`.
#[must_use]
pub fn buffer_entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }
}

/// Binding `binding`: texture view `v`.
#[must_use]
pub fn view_entry(binding: u32, v: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: wgpu::BindingResource::TextureView(v) }
}

/// A buffer of `size` bytes the shaders write (and the host may fill) and [`read_back`] copies from;
/// at least 256 bytes, so that even an empty one holds an element of any output array.
#[must_use]
pub fn output(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(256),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Run `work` (which submits and waits) with the device's validation and out-of-memory errors
/// captured and returned instead of panicking.
pub fn checked<T>(gpu: &Gpu, work: impl FnOnce() -> Result<T, GpuError>) -> Result<T, GpuError> {
    let memory = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = work();
    let errors = [pollster::block_on(validation.pop()), pollster::block_on(memory.pop())];
    match errors.into_iter().flatten().next() {
        Some(source) => Err(GpuError::Device { device: gpu.describe(), source }),
        None => out,
    }
}
