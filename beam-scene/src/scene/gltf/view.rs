//! The bytes of a buffer view, checked against its buffer: what the accessors ([`super::accessor`])
//! and their sparse substitutions ([`super::sparse`]) read from.

use std::rc::Rc;

/// The bytes of buffer `view`, checked to lie within its buffer.
pub(super) fn view_bytes<'b>(view: &gltf::buffer::View, buffers: &'b [Rc<Vec<u8>>]) -> Result<&'b [u8], String> {
    let data = &buffers[view.buffer().index()];
    let view_end = view.offset().checked_add(view.length());
    match view_end {
        Some(end) if end <= data.len() => Ok(&data[view.offset()..end]),
        _ => Err(format!(
            "buffer view {}: bytes {} to {} lie outside buffer {} ({} bytes)",
            view.index(),
            view.offset(),
            view_end.map_or_else(|| "∞".to_string(), |e| e.to_string()),
            view.buffer().index(),
            data.len()
        )),
    }
}
