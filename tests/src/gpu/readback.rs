//! Readbacks on the GPU reuse the mappable buffers earlier ones handed back (a frame reads back the
//! sizes the last one did), and each reads exactly its own bytes from a buffer that may be larger.

use super::device::adapter;
use crate::property::{Backend, Config, Outcome};
use beam_gpu::buffers::{map_with, read_back, readback, storage};

/// Words `0..n` uploaded, then read back through the pool's buffers: an 80 KB readback hands its
/// buffer (128 KB) back; a 48 KB one (within twice) takes that buffer and reads 48 KB, not the
/// buffer's size; a 300 KB one takes a new buffer, and an 80 KB one after it the first buffer
/// again (the smallest that fits); an empty one reads nothing. Every word read back equals the
/// word uploaded.
pub(super) fn gpu_readbacks_reuse_buffers(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let words: Vec<u32> = (0..75_000).collect();
    let source = storage(&gpu, "readback words", &words, wgpu::BufferUsages::COPY_SRC);
    let mut cases = 0;
    let mut read = |bytes: u64| -> Result<wgpu::Buffer, String> {
        let into = readback(&gpu, bytes);
        let buffer = into.buffer().clone();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&source, 0, &buffer, 0, bytes);
        gpu.queue.submit([encoder.finish()]);
        let as_words = |b: &[u8]| -> Vec<u32> {
            b.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
        };
        let got = map_with(&gpu, into, as_words).map_err(|e| e.to_string())?;
        if got[..] != words[..bytes as usize / 4] {
            return Err(format!("{bytes} bytes read back as {} words, not the uploaded ones", got.len()));
        }
        cases += 1;
        Ok(buffer)
    };
    let first = read(80_000)?;
    if read(48_000)? != first {
        return Err("a 48 KB readback did not reuse the 80 KB one's buffer".into());
    }
    if read(300_000)? == first {
        return Err("a 300 KB readback took a 128 KB buffer".into());
    }
    if read(80_000)? != first {
        return Err("an 80 KB readback after a 300 KB one did not take the smallest buffer that fits".into());
    }
    // An empty readback (a page without pairs) reads nothing.
    read(0)?;
    let encoder = gpu.device.create_command_encoder(&Default::default());
    let small: Vec<u32> = read_back(&gpu, encoder, &source, 4_000).map_err(|e| e.to_string())?;
    if small[..] != words[..1_000] {
        return Err("read_back through the pool returned other words".into());
    }
    Ok(Outcome { cases: cases + 1, note: "one buffer for 80 and 48 KB readbacks, another for 300 KB".into() })
}
