//! The interface both chunk storages implement.

use crate::{BlockId, ChunkSize, CoordError, LocalPos};

use super::StorageError;

/// One cubic chunk of [`BlockId`]s, however it is stored.
///
/// Rows run along x: the row at `(y, z)` holds voxels `(0..edge, y, z)`, and its occupancy mask
/// has bit `x` set iff voxel `(x, y, z)` is not [`BlockId::AIR`]. Every accessor checks its
/// position against [`size`](VoxelStorage::size) and returns an error instead of panicking, so a
/// [`LocalPos`] built for a 62^3 chunk used on an 8^3 chunk is a [`CoordError`].
///
/// Implemented by [`DenseChunk`](super::DenseChunk) (fast reads) and
/// [`PaletteChunk`](super::PaletteChunk) (small).
pub trait VoxelStorage {
    /// An all-air chunk of `size`.
    fn new_air(size: ChunkSize) -> Self
    where
        Self: Sized;

    /// The chunk's edge length.
    fn size(&self) -> ChunkSize;

    /// The voxel at `pos`.
    fn get(&self, pos: LocalPos) -> Result<BlockId, CoordError>;

    /// Writes `id` at `pos` and returns the id it replaced.
    fn set(&mut self, pos: LocalPos, id: BlockId) -> Result<BlockId, CoordError>;

    /// Sets every voxel to `id`.
    fn fill(&mut self, id: BlockId);

    /// Voxels that are not air.
    fn non_air_count(&self) -> usize;

    /// Occupancy of the x-row at `(y, z)`: bit `x` set iff voxel `(x, y, z)` is not air. Bits at
    /// and above the edge are zero.
    fn column_mask(&self, y: u32, z: u32) -> Result<u64, CoordError>;

    /// Copies the x-row at `(y, z)` into `out`, which must be exactly `edge` long.
    fn copy_row(&self, y: u32, z: u32, out: &mut [BlockId]) -> Result<(), StorageError>;

    /// Every voxel with its position, in linear order (x fastest, then y, then z).
    fn iter(&self) -> impl Iterator<Item = (LocalPos, BlockId)> + '_;

    /// Bytes this chunk holds on the heap (from its buffers' capacities).
    fn heap_bytes(&self) -> usize;

    /// `Some(id)` when the storage knows, without scanning, that every voxel is `id`. May
    /// answer `None` for a chunk that happens to be uniform.
    fn uniform(&self) -> Option<BlockId> {
        None
    }
}

/// The linear index of voxel `(0, y, z)`, after checking `y` and `z` against `size`.
#[inline]
pub(crate) fn row_start(size: ChunkSize, y: u32, z: u32) -> Result<usize, CoordError> {
    let e = size.edge();
    if y >= e || z >= e {
        return Err(CoordError::LocalOutOfChunk {
            pos: [0, y, z],
            edge: e,
        });
    }
    Ok(size.column_index(y, z) * size.edge_usize())
}

/// The position of linear index `i` (`i < volume`).
#[inline]
pub(crate) fn local_of(size: ChunkSize, i: usize) -> LocalPos {
    let e = size.edge_usize();
    LocalPos {
        x: (i % e) as u8,
        y: (i / e % e) as u8,
        z: (i / (e * e)) as u8,
    }
}
