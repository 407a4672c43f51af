//! Reading glTF accessors: the byte range of each element checked against its buffer view and
//! buffer (no arithmetic that can wrap), components decoded little-endian. An accessor without a
//! buffer view reads as zeros, and a sparse one has its substitutions applied.

use super::sparse;
use super::view::view_bytes;
use gltf::accessor::{DataType, Dimensions};
use std::borrow::Cow;
use std::rc::Rc;

/// The elements of `accessor` as `f32` components, `n` per element (`n` the size of its type;
/// integers normalized to [0, 1] or [−1, 1] when the accessor says so, else converted).
pub(super) fn floats(accessor: &gltf::Accessor, buffers: &[Rc<Vec<u8>>]) -> Result<Vec<f32>, String> {
    let normalized = accessor.normalized();
    let (data, layout) = elements(accessor, buffers)?;
    let mut out = Vec::with_capacity(layout.count * layout.components);
    for i in 0..layout.count {
        for c in 0..layout.components {
            let at = i * layout.stride + c * layout.component_size;
            let b = &data[at..at + layout.component_size];
            out.push(match (accessor.data_type(), normalized) {
                (DataType::F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                (DataType::U8, false) => f32::from(b[0]),
                (DataType::U8, true) => f32::from(b[0]) / 255.0,
                (DataType::I8, false) => f32::from(b[0] as i8),
                (DataType::I8, true) => (f32::from(b[0] as i8) / 127.0).max(-1.0),
                (DataType::U16, false) => f32::from(u16::from_le_bytes([b[0], b[1]])),
                (DataType::U16, true) => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
                (DataType::I16, false) => f32::from(i16::from_le_bytes([b[0], b[1]])),
                (DataType::I16, true) => (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0),
                (DataType::U32, false) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
                (DataType::U32, true) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32 / u32::MAX as f32,
            });
        }
    }
    Ok(out)
}

/// The elements of the index accessor `accessor` (scalars of unsigned bytes, shorts or ints).
pub(super) fn indices(accessor: &gltf::Accessor, buffers: &[Rc<Vec<u8>>]) -> Result<Vec<u32>, String> {
    if accessor.dimensions() != Dimensions::Scalar
        || !matches!(accessor.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(format!(
            "indices accessor {}: must be scalars of unsigned bytes, shorts or ints, not {:?} of {:?}",
            accessor.index(),
            accessor.dimensions(),
            accessor.data_type()
        ));
    }
    let (data, layout) = elements(accessor, buffers)?;
    Ok((0..layout.count)
        .map(|i| {
            let b = &data[i * layout.stride..i * layout.stride + layout.component_size];
            match b.len() {
                1 => u32::from(b[0]),
                2 => u32::from(u16::from_le_bytes([b[0], b[1]])),
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            }
        })
        .collect())
}

/// Where an accessor's elements lie in the slice [`elements`] returns.
struct Layout {
    /// Number of elements.
    count: usize,
    /// Bytes from one element to the next.
    stride: usize,
    /// Components per element.
    components: usize,
    /// Bytes per component.
    component_size: usize,
}

/// Most bytes the elements of an accessor without a buffer view (zeros, or sparse values over
/// zeros) may take: a few bytes of JSON must not ask for gigabytes.
const MAX_ZERO_BYTES: usize = 1 << 26;

/// The bytes of `accessor`'s elements and their layout: from its buffer view (from its first
/// element's start to its last one's end, an error when any lies outside the view or buffer),
/// zeros without a buffer view, and with a sparse substitution applied ([`sparse::apply`]).
fn elements<'b>(accessor: &gltf::Accessor, buffers: &'b [Rc<Vec<u8>>]) -> Result<(Cow<'b, [u8]>, Layout), String> {
    let at = format!("accessor {}", accessor.index());
    let component_size = accessor.data_type().size();
    let components = accessor.dimensions().multiplicity();
    let size = component_size * components;
    let count = accessor.count();
    let (dense, layout) = match accessor.view() {
        Some(view) => {
            let (data, stride) = viewed(&at, accessor, &view, buffers, size)?;
            (Cow::Borrowed(data), Layout { count, stride, components, component_size })
        }
        None => {
            let bytes = count.checked_mul(size).filter(|&b| b <= MAX_ZERO_BYTES).ok_or_else(|| {
                format!("{at}: {count} elements without a bufferView (zeros) take more than {MAX_ZERO_BYTES} bytes")
            })?;
            (Cow::Owned(vec![0; bytes]), Layout { count, stride: size, components, component_size })
        }
    };
    let Some(substitution) = accessor.sparse() else {
        return Ok((dense, layout));
    };
    let mut tight = match dense {
        Cow::Owned(v) => v,
        Cow::Borrowed(d) => (0..count).flat_map(|i| &d[i * layout.stride..i * layout.stride + size]).copied().collect(),
    };
    sparse::apply(&at, &substitution, buffers, &mut tight, size)?;
    Ok((Cow::Owned(tight), Layout { stride: size, ..layout }))
}

/// The bytes of `accessor`'s `count` elements of `size` bytes in its buffer `view`, from its first
/// element's start to its last one's end, and the stride between them.
fn viewed<'b>(
    at: &str,
    accessor: &gltf::Accessor,
    view: &gltf::buffer::View,
    buffers: &'b [Rc<Vec<u8>>],
    size: usize,
) -> Result<(&'b [u8], usize), String> {
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "{at}: buffer view {} has a byteStride of {stride}, less than the {size} bytes of an element",
            view.index()
        ));
    }
    let count = accessor.count();
    if count == 0 {
        return Ok((&[], stride));
    }
    let too_long = || {
        format!(
            "{at}: {count} elements from byte {} do not fit in buffer view {} ({} bytes)",
            accessor.offset(),
            view.index(),
            view.length()
        )
    };
    let span = stride.checked_mul(count - 1).and_then(|s| s.checked_add(size)).ok_or_else(too_long)?;
    if accessor.offset().checked_add(span).is_none_or(|end| end > view.length()) {
        return Err(too_long());
    }
    let data = view_bytes(view, buffers)?;
    Ok((&data[accessor.offset()..accessor.offset() + span], stride))
}
