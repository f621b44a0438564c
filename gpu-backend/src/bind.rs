//! Small helpers for bind groups.

use wgpu::{BindGroupEntry, Buffer};

/// The whole of `buffer` at `binding`.
pub(crate) fn buffer_entry(binding: u32, buffer: &Buffer) -> BindGroupEntry<'_> {
    BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}
