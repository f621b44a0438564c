//! The kinds of chunk data the gigabuffer stores, one buffer set per kind.

use std::fmt;

use voxel_core::formats::{BlockVertex, ClutterUnit, DrawBlock, PackedQuad};

/// One kind of per-chunk GPU data. Each kind lives in its own gigabuffer (a set of pages) whose
/// element type is fixed, so offsets are element indices of that type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DataKind {
    /// Greedy quads, [`PackedQuad`], 8 bytes: a chunk's opaque and transparent quad layers,
    /// each grouped by face direction.
    Quads,
    /// Smooth-surface vertices, [`BlockVertex`], 16 bytes.
    SmoothVertices,
    /// Smooth-surface quads, as `u32` words (4 bytes): a chunk's quads are the bytes of the
    /// mesher's [`SmoothQuads`](voxel_core::formats::SmoothQuads) (compact 6-byte records, or 4
    /// `u16` / `u32` vertex indices per quad, relative to the chunk's first smooth vertex),
    /// zero-padded to a whole word; the draw record carries the form.
    SmoothQuads,
    /// Clutter instances, [`ClutterUnit`], 20 bytes.
    Clutter,
    /// Surface blocks, [`DrawBlock`], 4 bytes: the block list far chunks are raycast from.
    DrawBlocks,
}

impl DataKind {
    /// Number of kinds.
    pub const COUNT: usize = 5;

    /// Every kind, in index order.
    pub const ALL: [DataKind; DataKind::COUNT] = [
        DataKind::Quads,
        DataKind::SmoothVertices,
        DataKind::SmoothQuads,
        DataKind::Clutter,
        DataKind::DrawBlocks,
    ];

    /// Position in [`DataKind::ALL`].
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Bytes per element. Every size is a multiple of 4 (wgpu's copy alignment), so every
    /// element offset is a valid copy offset.
    pub const fn element_size(self) -> u32 {
        (match self {
            DataKind::Quads => size_of::<PackedQuad>(),
            DataKind::SmoothVertices => size_of::<BlockVertex>(),
            DataKind::SmoothQuads => size_of::<u32>(),
            DataKind::Clutter => size_of::<ClutterUnit>(),
            DataKind::DrawBlocks => size_of::<DrawBlock>(),
        }) as u32
    }

    /// The name used in buffer labels and reports.
    pub const fn name(self) -> &'static str {
        match self {
            DataKind::Quads => "quads",
            DataKind::SmoothVertices => "smooth vertices",
            DataKind::SmoothQuads => "smooth quads",
            DataKind::Clutter => "clutter",
            DataKind::DrawBlocks => "draw blocks",
        }
    }
}

const _: () = {
    let mut i = 0;
    while i < DataKind::COUNT {
        assert!(
            DataKind::ALL[i]
                .element_size()
                .is_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT as u32),
            "element sizes must be multiples of the copy alignment"
        );
        assert!(DataKind::ALL[i].index() == i, "ALL is in index order");
        i += 1;
    }
};

impl fmt::Display for DataKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One value per [`DataKind`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PerKind<T>(pub [T; DataKind::COUNT]);

impl<T> PerKind<T> {
    /// The value of `kind`.
    pub fn get(&self, kind: DataKind) -> &T {
        &self.0[kind.index()]
    }

    /// The value of `kind`, mutably.
    pub fn get_mut(&mut self, kind: DataKind) -> &mut T {
        &mut self.0[kind.index()]
    }

    /// `(kind, value)` pairs in kind order.
    pub fn iter(&self) -> impl Iterator<Item = (DataKind, &T)> {
        DataKind::ALL.into_iter().zip(self.0.iter())
    }
}
