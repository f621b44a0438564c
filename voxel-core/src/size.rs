//! The chunk edge lengths the storage and meshers support.

use core::fmt;

/// Edge length of a cubic chunk, in voxels.
///
/// `S62` is the "64 with a one-voxel apron" size of binary greedy meshing: a 62^3 chunk plus its
/// one-voxel border from the neighbours is 64^3, so each padded column fits one `u64`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ChunkSize {
    /// 8^3 voxels (Ascendant's chunk size).
    S8,
    /// 16^3 voxels (Lum's block size).
    S16,
    /// 32^3 voxels.
    S32,
    /// 62^3 voxels: 64^3 once padded with a one-voxel apron.
    S62,
}

/// An edge length that is not one of the supported sizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnsupportedChunkSize(pub u32);

impl fmt::Display for UnsupportedChunkSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unsupported chunk edge {} (supported: 8, 16, 32, 62)",
            self.0
        )
    }
}

#[cfg(feature = "std")]
impl std::error::Error for UnsupportedChunkSize {}

impl ChunkSize {
    /// Every supported size, smallest first.
    pub const ALL: [ChunkSize; 4] = [
        ChunkSize::S8,
        ChunkSize::S16,
        ChunkSize::S32,
        ChunkSize::S62,
    ];

    /// Edge length in voxels.
    #[inline]
    pub const fn edge(self) -> u32 {
        match self {
            ChunkSize::S8 => 8,
            ChunkSize::S16 => 16,
            ChunkSize::S32 => 32,
            ChunkSize::S62 => 62,
        }
    }

    /// Edge length as `usize`, for indexing.
    #[inline]
    pub const fn edge_usize(self) -> usize {
        self.edge() as usize
    }

    /// Voxels in the chunk: `edge^3`.
    #[inline]
    pub const fn volume(self) -> usize {
        let e = self.edge_usize();
        e * e * e
    }

    /// Columns in the chunk: `edge^2` (one occupancy mask each).
    #[inline]
    pub const fn columns(self) -> usize {
        let e = self.edge_usize();
        e * e
    }

    /// Edge of the padded neighbourhood: `edge + 2` (at most 64).
    #[inline]
    pub const fn padded_edge(self) -> usize {
        self.edge_usize() + 2
    }

    /// The size with this edge length, or an error naming the rejected value.
    pub const fn from_edge(edge: u32) -> Result<ChunkSize, UnsupportedChunkSize> {
        match edge {
            8 => Ok(ChunkSize::S8),
            16 => Ok(ChunkSize::S16),
            32 => Ok(ChunkSize::S32),
            62 => Ok(ChunkSize::S62),
            other => Err(UnsupportedChunkSize(other)),
        }
    }

    /// Linear index of a local position: `x + edge * (y + edge * z)` (x fastest).
    ///
    /// The caller guarantees `x, y, z < edge` (a [`LocalPos`](crate::LocalPos) checked against
    /// this size does).
    #[inline]
    pub const fn linearize(self, x: u32, y: u32, z: u32) -> usize {
        let e = self.edge_usize();
        x as usize + e * (y as usize + e * z as usize)
    }

    /// Column index of the x-row at `(y, z)`: `y + edge * z`. Occupancy masks are stored in
    /// this order, one bit per x.
    #[inline]
    pub const fn column_index(self, y: u32, z: u32) -> usize {
        y as usize + self.edge_usize() * z as usize
    }
}
