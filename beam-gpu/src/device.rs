//! Headless device set-up: an adapter without a window or surface (Mesa lavapipe in CI, a real GPU
//! where there is one), its name and backend, and a clear error when there is none.

use crate::error::GpuError;
use crate::pool::BufferPool;
use beam_render::cpu_clock::thread_cpu_seconds;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// A device and its queue with what the adapter says of itself, and how long beam has waited on
/// it ([`Gpu::traffic`]).
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name, backend, driver.
    pub info: wgpu::AdapterInfo,
    waited_ns: AtomicU64,
    read_back: AtomicU64,
    upload_ns: AtomicU64,
    uploaded: AtomicU64,
    unpack_ns: AtomicU64,
    /// Mappable buffers that readbacks handed back, for the next ones ([`crate::buffers::readback`]).
    pub(crate) readbacks: BufferPool,
    /// Scratch buffers that passes handed back, for the next ones ([`crate::scratch::scratch`]).
    pub(crate) scratch: Arc<BufferPool>,
}

/// What beam's passes have cost on the host side of the bus so far, summed over its calls: the
/// time blocked waiting for the device (everything else a caller times is host work), the bytes
/// read back and uploaded, and the host's time in both.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Traffic {
    /// Seconds blocked on the device: polling for a readback, and in submissions the device held
    /// back until the one before was done (lavapipe does; [`Gpu::submit`]).
    pub waited_seconds: f64,
    /// Bytes copied back to the host.
    pub bytes_read_back: u64,
    /// Host seconds creating and filling buffers and textures from host data (`crate::buffers`).
    pub upload_seconds: f64,
    /// Bytes uploaded.
    pub bytes_uploaded: u64,
    /// Host seconds reading mapped readbacks (unpacking them where they are mapped), waits excluded.
    pub unpack_seconds: f64,
}

impl std::ops::Sub for Traffic {
    type Output = Self;

    fn sub(self, earlier: Self) -> Self {
        Self {
            waited_seconds: self.waited_seconds - earlier.waited_seconds,
            bytes_read_back: self.bytes_read_back - earlier.bytes_read_back,
            upload_seconds: self.upload_seconds - earlier.upload_seconds,
            bytes_uploaded: self.bytes_uploaded - earlier.bytes_uploaded,
            unpack_seconds: self.unpack_seconds - earlier.unpack_seconds,
        }
    }
}

fn nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

impl Gpu {
    /// The default adapter (`WGPU_BACKEND=vulkan|gl|…` picks a backend) with its own limits.
    /// Errors say that no adapter exists and how to get one (Mesa's lavapipe on Linux).
    pub fn new() -> Result<Self, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
        let adapter = pollster::block_on(
            instance.request_adapter(&wgpu::RequestAdapterOptions { compatible_surface: None, ..Default::default() }),
        )
        .map_err(|source| {
            // An unknown `WGPU_BACKEND` name is dropped by wgpu, which then finds no adapter: say so
            // rather than advise installing a driver.
            const KNOWN: [&str; 11] =
                ["vulkan", "vk", "dx12", "d3d12", "metal", "mtl", "opengl", "gles", "gl", "webgpu", "noop"];
            if let Ok(v) = std::env::var("WGPU_BACKEND") {
                let unknown: Vec<String> = v
                    .split(',')
                    .map(str::trim)
                    .filter(|b| !KNOWN.contains(&b.to_lowercase().as_str()))
                    .map(String::from)
                    .collect();
                if !unknown.is_empty() {
                    return GpuError::UnknownBackend { value: v, unknown };
                }
            }
            GpuError::NoAdapter { source }
        })?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("beam"),
            required_limits: adapter.limits(),
            // Timestamps time the atlas passes on the GPU itself (`crate::timestamps`); 64-bit
            // atomics find the atlas's nearest hits by compute (`shaders/beam_texels.wgsl`).
            required_features: adapter.features()
                & (wgpu::Features::TIMESTAMP_QUERY
                    | wgpu::Features::SHADER_INT64
                    | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX),
            ..Default::default()
        }))
        .map_err(|source| GpuError::OpenDevice {
            adapter: info.name.clone(),
            backend: info.backend,
            source,
        })?;
        Ok(Self::from_device(device, queue, info))
    }

    /// beam on a device and queue the caller opened (an engine's), `info` its adapter's.
    #[must_use]
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue, info: wgpu::AdapterInfo) -> Self {
        let zero = || AtomicU64::new(0);
        Self {
            device,
            queue,
            info,
            waited_ns: zero(),
            read_back: zero(),
            upload_ns: zero(),
            uploaded: zero(),
            unpack_ns: zero(),
            readbacks: BufferPool::readbacks(),
            scratch: Arc::new(BufferPool::scratch()),
        }
    }

    /// Waits and readbacks so far; subtract two to get an interval's.
    #[must_use]
    pub fn traffic(&self) -> Traffic {
        let seconds = |ns: &AtomicU64| Duration::from_nanos(ns.load(Ordering::Relaxed)).as_secs_f64();
        Traffic {
            waited_seconds: seconds(&self.waited_ns),
            bytes_read_back: self.read_back.load(Ordering::Relaxed),
            upload_seconds: seconds(&self.upload_ns),
            bytes_uploaded: self.uploaded.load(Ordering::Relaxed),
            unpack_seconds: seconds(&self.unpack_ns),
        }
    }

    /// Submit `buffers` to the queue. Where the device holds a submission back until the one
    /// before is done (lavapipe does), the time blocked (the call's time less the calling thread's
    /// CPU time in it) counts as waited ([`Traffic::waited_seconds`]).
    pub fn submit<I: IntoIterator<Item = wgpu::CommandBuffer>>(&self, buffers: I) -> wgpu::SubmissionIndex {
        let (start, cpu) = (Instant::now(), thread_cpu_seconds());
        let index = self.queue.submit(buffers);
        if let (Some(before), Some(after)) = (cpu, thread_cpu_seconds()) {
            let blocked = start.elapsed().as_secs_f64() - (after - before);
            self.waited_ns.fetch_add((blocked.max(0.0) * 1e9) as u64, Ordering::Relaxed);
        }
        index
    }

    /// Count a wait of `waited` that read back `bytes`, unpacked in `unpacking`.
    pub(crate) fn record(&self, waited: Duration, bytes: usize, unpacking: Duration) {
        self.waited_ns.fetch_add(nanos(waited), Ordering::Relaxed);
        self.read_back.fetch_add(bytes as u64, Ordering::Relaxed);
        self.unpack_ns.fetch_add(nanos(unpacking), Ordering::Relaxed);
    }

    /// Count an upload of `bytes` that took the host `took`.
    pub(crate) fn record_upload(&self, took: Duration, bytes: usize) {
        self.upload_ns.fetch_add(nanos(took), Ordering::Relaxed);
        self.uploaded.fetch_add(bytes as u64, Ordering::Relaxed);
    }

    /// `name (backend)`.
    #[must_use]
    pub fn describe(&self) -> String {
        format!("{} ({:?})", self.info.name, self.info.backend)
    }

    /// True on a GPU emulated by the CPU (Mesa's lavapipe, as in CI): correct, but its rasterizer
    /// is orders of magnitude slower than a real GPU's.
    #[must_use]
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }
}
