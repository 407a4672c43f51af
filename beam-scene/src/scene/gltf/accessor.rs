//! Reading glTF accessors: the byte range of each element checked against its buffer view and
//! buffer (no arithmetic that can wrap), components decoded little-endian.

use gltf::accessor::{DataType, Dimensions};
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

/// The bytes of `accessor`'s elements, from its first element's start to its last one's end, and
/// their layout; an error when any of them lies outside its buffer view or buffer, or the
/// accessor is sparse or has no buffer view.
fn elements<'b>(accessor: &gltf::Accessor, buffers: &'b [Rc<Vec<u8>>]) -> Result<(&'b [u8], Layout), String> {
    let at = format!("accessor {}", accessor.index());
    if accessor.sparse().is_some() {
        return Err(format!("{at}: sparse accessors are not read"));
    }
    let Some(view) = accessor.view() else {
        return Err(format!("{at}: has no bufferView"));
    };
    let component_size = accessor.data_type().size();
    let components = accessor.dimensions().multiplicity();
    let size = component_size * components;
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "{at}: buffer view {} has a byteStride of {stride}, less than the {size} bytes of an element",
            view.index()
        ));
    }
    let count = accessor.count();
    let layout = Layout { count, stride, components, component_size };
    if count == 0 {
        return Ok((&[], layout));
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
    let data = &buffers[view.buffer().index()];
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > data.len()) {
        return Err(format!(
            "buffer view {}: bytes {} to {} lie outside buffer {} ({} bytes)",
            view.index(),
            view.offset(),
            view_end.map_or_else(|| "∞".to_string(), |e| e.to_string()),
            view.buffer().index(),
            data.len()
        ));
    }
    let start = view.offset() + accessor.offset();
    Ok((&data[start..start + span], layout))
}
