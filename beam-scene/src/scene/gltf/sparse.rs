//! Sparse glTF accessors: the elements a sparse substitution names (by index) replaced by its
//! values, every byte range and index checked.

use super::view::view_bytes;
use gltf::accessor::sparse::{IndexType, Sparse};
use std::rc::Rc;

/// Replace the elements of `data` (tightly packed, `size` bytes each) that `sparse` names by its
/// values. `at` names the accessor in errors.
pub(super) fn apply(
    at: &str,
    sparse: &Sparse,
    buffers: &[Rc<Vec<u8>>],
    data: &mut [u8],
    size: usize,
) -> Result<(), String> {
    let n = sparse.count();
    let count = data.len().checked_div(size).unwrap_or(0);
    let indices = sparse.indices();
    let index_size = match indices.index_type() {
        IndexType::U8 => 1,
        IndexType::U16 => 2,
        IndexType::U32 => 4,
    };
    let index_bytes = range(view_bytes(&indices.view(), buffers)?, indices.offset(), n, index_size)
        .ok_or_else(|| format!("{at}: its {n} sparse indices do not fit in buffer view {}", indices.view().index()))?;
    let values = sparse.values();
    let value_bytes = range(view_bytes(&values.view(), buffers)?, values.offset(), n, size)
        .ok_or_else(|| format!("{at}: its {n} sparse values do not fit in buffer view {}", values.view().index()))?;
    for (k, b) in index_bytes.chunks_exact(index_size).enumerate() {
        let i = match b.len() {
            1 => usize::from(b[0]),
            2 => usize::from(u16::from_le_bytes([b[0], b[1]])),
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
        };
        if i >= count {
            return Err(format!("{at}: sparse index {i} out of range ({count} elements)"));
        }
        data[i * size..(i + 1) * size].copy_from_slice(&value_bytes[k * size..(k + 1) * size]);
    }
    Ok(())
}

/// The `n` elements of `size` bytes from byte `offset` of `view`, if they lie within it.
fn range(view: &[u8], offset: usize, n: usize, size: usize) -> Option<&[u8]> {
    let end = n.checked_mul(size)?.checked_add(offset)?;
    view.get(offset..end)
}
