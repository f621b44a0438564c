//! The per-frame upload batch: every upload of a frame is copied into one CPU arena, and
//! [`StagingQueue::record`] moves the whole arena to the GPU through one staging buffer.
//!
//! **Why not `queue.write_buffer` per upload.** Each `write_buffer` call gets its own staging
//! allocation inside wgpu; a frame that streams in hundreds of chunks (several layers each)
//! would make hundreds of them. Here a frame costs one staging buffer (created mapped, filled
//! with one memcpy, unmapped) and one `copy_buffer_to_buffer` per contiguous destination run,
//! recorded into the caller's command encoder, so the copies are ordered before whatever the
//! encoder records next (the cull and draw passes of the same frame). The staging buffer is
//! dropped after recording; wgpu keeps it alive until the GPU has executed the copies.
//! (Reusing staging memory across frames, e.g. with a ring of mapped buffers, is a possible
//! refinement; the copy count and byte count would not change.)

use wgpu::{Buffer, BufferDescriptor, BufferUsages, CommandEncoder, Device};

use voxel_core::formats::DataKind;

use crate::device::alloc::AllocError;

/// A copy waiting for the next flush: `size` bytes from `src` in the arena to `dst` in page
/// `page` of `kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PendingCopy {
    pub kind: DataKind,
    pub page: u32,
    pub dst: u64,
    pub src: u64,
    pub size: u64,
}

/// What one flush moved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FlushStats {
    /// Bytes copied from the staging buffer into pages.
    pub bytes: u64,
    /// `copy_buffer_to_buffer` commands recorded (after coalescing).
    pub copies: u32,
}

/// The CPU side of the batch.
#[derive(Debug, Default)]
pub(crate) struct StagingQueue {
    arena: Vec<u8>,
    copies: Vec<PendingCopy>,
}

impl StagingQueue {
    /// Queues `data` for byte offset `dst` of page `page` of `kind`. Merges with the previous
    /// copy when both the arena and the destination continue it.
    pub(super) fn push(&mut self, kind: DataKind, page: u32, dst: u64, data: &[u8]) {
        if data.is_empty() {
            return;
        }
        let src = self.arena.len() as u64;
        self.arena.extend_from_slice(data);
        let size = data.len() as u64;
        if let Some(last) = self.copies.last_mut()
            && last.kind == kind
            && last.page == page
            && last.src + last.size == src
            && last.dst + last.size == dst
        {
            last.size += size;
            return;
        }
        self.copies.push(PendingCopy {
            kind,
            page,
            dst,
            src,
            size,
        });
    }

    /// Bytes waiting.
    pub(super) fn pending_bytes(&self) -> u64 {
        self.arena.len() as u64
    }

    /// The copies waiting.
    #[cfg(test)]
    pub(super) fn pending_copies(&self) -> &[PendingCopy] {
        &self.copies
    }

    /// Records every pending copy into `encoder` through one staging buffer and empties the
    /// queue (keeping its capacity). `destination(kind, page)` returns the page's buffer. When
    /// the device refuses the staging buffer nothing is recorded and the copies stay queued.
    pub(super) fn record<'a>(
        &mut self,
        device: &Device,
        encoder: &mut CommandEncoder,
        destination: impl Fn(DataKind, u32) -> &'a Buffer,
    ) -> Result<FlushStats, AllocError> {
        if self.copies.is_empty() {
            self.arena.clear();
            return Ok(FlushStats::default());
        }
        // Every element size is a multiple of 4, so the arena length already is; the padding
        // only guards the copy-size rule should that ever change.
        let size = self
            .arena
            .len()
            .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT as usize);
        self.arena.resize(size, 0);
        let staging = crate::device::alloc::create_buffer(
            device,
            &BufferDescriptor {
                label: Some("gigabuffer staging"),
                size: size as u64,
                usage: BufferUsages::COPY_SRC,
                mapped_at_creation: true,
            },
        )?;
        staging
            .slice(..)
            .get_mapped_range_mut()
            .expect("a buffer created mapped is mapped over its whole range")
            .copy_from_slice(&self.arena);
        staging.unmap();
        let mut stats = FlushStats::default();
        for copy in &self.copies {
            encoder.copy_buffer_to_buffer(
                &staging,
                copy.src,
                destination(copy.kind, copy.page),
                copy.dst,
                copy.size,
            );
            stats.bytes += copy.size;
            stats.copies += 1;
        }
        self.arena.clear();
        self.copies.clear();
        Ok(stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contiguous_pushes_coalesce() {
        let mut q = StagingQueue::default();
        q.push(DataKind::Quads, 0, 0, &[1; 16]);
        q.push(DataKind::Quads, 0, 16, &[2; 8]);
        assert_eq!(q.pending_copies().len(), 1);
        assert_eq!(q.pending_copies()[0].size, 24);
        // A gap in the destination, another page, another kind: new copies.
        q.push(DataKind::Quads, 0, 64, &[3; 8]);
        q.push(DataKind::Quads, 1, 72, &[4; 8]);
        q.push(DataKind::Clutter, 1, 80, &[5; 20]);
        assert_eq!(q.pending_copies().len(), 4);
        assert_eq!(q.pending_bytes(), 16 + 8 + 8 + 8 + 20);
        q.push(DataKind::Clutter, 1, 100, &[]);
        assert_eq!(q.pending_copies().len(), 4, "empty data queues nothing");
    }
}
