//! How large each kind's gigabuffer may grow.

use voxel_core::formats::{DataKind, PerKind};

/// How large each kind's gigabuffer may grow, and allocator bounds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GigabufferConfig {
    /// Bytes per kind (rounded down to whole elements); 0 disables the kind.
    pub bytes: PerKind<u64>,
    /// Page size cap below the device's binding limit (`None`: the device limit). Tests use it
    /// to exercise paging with small buffers.
    pub max_page_bytes: Option<u64>,
    /// Resident chunks at most. Also sizes each page's allocator metadata, which
    /// `offset-allocator` reserves up front: two nodes of 32 bytes per chunk, so 64 bytes of
    /// CPU memory per chunk per created page (32 MiB per page for 2^19 chunks).
    pub max_chunks: u32,
}

impl GigabufferConfig {
    /// Every kind disabled; add kinds with [`with_bytes`](Self::with_bytes).
    pub fn empty() -> Self {
        GigabufferConfig {
            bytes: PerKind::default(),
            max_page_bytes: None,
            max_chunks: 1 << 16,
        }
    }

    /// Project Ascendant's budget, about 400 MB in all: 256 MiB of greedy quads (32 M quads),
    /// 64 MiB of smooth vertices, 32 MiB of smooth quads, 32 MiB of clutter, 16 MiB of draw
    /// blocks, for up to 2^19 chunks.
    pub fn ascendant() -> Self {
        const MIB: u64 = 1 << 20;
        GigabufferConfig::empty()
            .with_bytes(DataKind::Quads, 256 * MIB)
            .with_bytes(DataKind::SmoothVertices, 64 * MIB)
            .with_bytes(DataKind::SmoothQuads, 32 * MIB)
            .with_bytes(DataKind::Clutter, 32 * MIB)
            .with_bytes(DataKind::DrawBlocks, 16 * MIB)
            .with_max_chunks(1 << 19)
    }

    /// Sets the byte budget of `kind`.
    pub fn with_bytes(mut self, kind: DataKind, bytes: u64) -> Self {
        *self.bytes.get_mut(kind) = bytes;
        self
    }

    /// Caps the page size.
    pub fn with_max_page_bytes(mut self, bytes: u64) -> Self {
        self.max_page_bytes = Some(bytes);
        self
    }

    /// Sets the resident chunk limit.
    pub fn with_max_chunks(mut self, chunks: u32) -> Self {
        self.max_chunks = chunks;
        self
    }
}
