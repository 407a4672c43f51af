//! Headless device set-up: an adapter without a window or surface (Mesa lavapipe in CI, a real GPU
//! where there is one), its name and backend, and a clear error when there is none.

use crate::GpuError;

/// A device and its queue with what the adapter says of itself.
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name, backend, driver.
    pub info: wgpu::AdapterInfo,
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
            ..Default::default()
        }))
        .map_err(|source| GpuError::OpenDevice {
            adapter: info.name.clone(),
            backend: info.backend,
            source,
        })?;
        Ok(Self { device, queue, info })
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
