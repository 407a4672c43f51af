//! Arrays kept in 2D textures rather than storage buffers, for data that grows with texels (a
//! level's radiance in the composite, the caustic maps' flux): a storage binding of the device
//! bounds a buffer (128 MiB on many, less where an engine asks for less), a texture only by its
//! dimensions. Element `i` lies at `(i mod width, i / width)` of a texture [`width`] texels wide.

use crate::{Gpu, GpuError};

/// Texels per row: a power of two (so that a row of up to 16-byte texels is a multiple of wgpu's
/// 256-byte copy alignment), at most 4096 and the device's widest texture.
#[must_use]
pub(crate) fn width(gpu: &Gpu) -> u32 {
    let widest = gpu.device.limits().max_texture_dimension_2d.clamp(64, 4096);
    1 << (31 - widest.leading_zeros())
}

/// Rows of a texture of `len` elements (at least one).
#[must_use]
pub(crate) fn rows(gpu: &Gpu, len: usize) -> u32 {
    u32::try_from(len.div_ceil(width(gpu) as usize).max(1)).unwrap_or(u32::MAX)
}

/// True when `len` elements fit one texture of the device.
#[must_use]
pub(crate) fn fits(gpu: &Gpu, len: usize) -> bool {
    rows(gpu, len) <= gpu.device.limits().max_texture_dimension_2d
}

/// A texture of `len` elements of `format` (zeroed by wgpu).
#[must_use]
pub(crate) fn texture(
    gpu: &Gpu,
    label: &str,
    len: usize,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    texture_2d(gpu, label, (width(gpu), rows(gpu, len)), format, usage)
}

/// A 2D texture of `width × height` texels of `format`, one mip level, one sample.
#[must_use]
pub(crate) fn texture_2d(
    gpu: &Gpu,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A texture holding `items` (each one texel of `format`, which must be as large as `T`).
#[must_use]
pub(crate) fn upload<T: bytemuck::Pod>(
    gpu: &Gpu,
    label: &str,
    items: &[T],
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    let out =
        texture(gpu, label, items.len(), format, wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST);
    let size = out.size();
    let mut texels = vec![T::zeroed(); (size.width * size.height) as usize];
    texels[..items.len()].copy_from_slice(items);
    let start = std::time::Instant::now();
    gpu.queue.write_texture(
        out.as_image_copy(),
        bytemuck::cast_slice(&texels),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(size.width * size_of::<T>() as u32),
            rows_per_image: Some(size.height),
        },
        size,
    );
    gpu.record_upload(start.elapsed(), texels.len() * size_of::<T>());
    out
}

/// Hand `read` the texels of `texture` (with `COPY_SRC`, `T` a texel) row after row: where they
/// are mapped when a row is a whole number of wgpu's copy alignments (as every texture of
/// [`texture`] is), so that the caller converts them without a copy in between; else gathered
/// from the padded rows first.
pub(crate) fn read_back_with<T: bytemuck::Pod, R>(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    read: impl FnOnce(&[T]) -> R,
) -> Result<R, GpuError> {
    let size = texture.size();
    let row = size.width as usize * size_of::<T>();
    let bytes_per_row = (row as u32).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let readback = crate::buffers::readback(gpu, u64::from(bytes_per_row) * u64::from(size.height));
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: readback.buffer(),
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(bytes_per_row),
                rows_per_image: Some(size.height),
            },
        },
        size,
    );
    gpu.submit([encoder.finish()]);
    // Mapped ranges are 8-byte aligned; copied only where a backend mapped them otherwise.
    crate::buffers::map_with(gpu, readback, |bytes| {
        if row != bytes_per_row as usize {
            // One copy: each padded row's texels into their place.
            let mut texels = vec![T::zeroed(); size.width as usize * size.height as usize];
            let rows = bytemuck::cast_slice_mut::<T, u8>(&mut texels).chunks_mut(row);
            for (out, padded) in rows.zip(bytes.chunks(bytes_per_row as usize)) {
                out.copy_from_slice(&padded[..row]);
            }
            return read(&texels);
        }
        match bytemuck::try_cast_slice(bytes) {
            Ok(texels) => read(texels),
            Err(_) => read(&bytemuck::pod_collect_to_vec(bytes)),
        }
    })
}
