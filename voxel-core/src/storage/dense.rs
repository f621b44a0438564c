//! [`DenseChunk`]: one [`BlockId`] per voxel, with stored per-row occupancy masks.

use alloc::vec;
use alloc::vec::Vec;

use crate::{BlockId, ChunkSize, CoordError, LocalPos};

use super::packed_bits::low_bits;
use super::traits::{local_of, row_start};
use super::{PaletteChunk, StorageError, VoxelStorage};

/// A chunk stored as a flat array of `edge^3` ids, x fastest (`x + edge * (y + edge * z)`, see
/// [`ChunkSize::linearize`]), plus one `u64` occupancy mask per x-row (in
/// [`ChunkSize::column_index`] order, bit `x` set iff the voxel is not air) and a non-air count.
///
/// Every write ([`set`](VoxelStorage::set), [`fill`](VoxelStorage::fill), the constructors and
/// conversions) keeps the masks and the count up to date, so meshers can read
/// [`columns`](DenseChunk::columns) directly. Costs 2 bytes per voxel plus 8 bytes per row.
///
/// ```
/// use voxel_core::{BlockId, ChunkSize, LocalPos};
/// use voxel_core::storage::{DenseChunk, VoxelStorage};
///
/// let mut chunk = DenseChunk::new(ChunkSize::S8);
/// let pos = LocalPos::new(3, 1, 2, ChunkSize::S8)?;
/// assert_eq!(chunk.set(pos, BlockId(5))?, BlockId::AIR);
/// assert_eq!(chunk.column_mask(1, 2)?, 1 << 3);
/// assert_eq!(chunk.as_slice()[ChunkSize::S8.linearize(3, 1, 2)], BlockId(5));
/// // A position valid for a 62^3 chunk is an error here, not a panic.
/// assert!(chunk.get(LocalPos::new(40, 0, 0, ChunkSize::S62)?).is_err());
/// # Ok::<(), voxel_core::CoordError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DenseChunk {
    size: ChunkSize,
    voxels: Vec<BlockId>,
    columns: Vec<u64>,
    non_air: usize,
}

/// Occupancy mask of one row.
#[inline]
fn row_mask(row: &[BlockId]) -> u64 {
    row.iter()
        .enumerate()
        .fold(0, |m, (x, v)| m | (u64::from(!v.is_air()) << x))
}

impl DenseChunk {
    /// An all-air chunk.
    pub fn new(size: ChunkSize) -> Self {
        Self::filled(size, BlockId::AIR)
    }

    /// A chunk with every voxel set to `id`.
    pub fn filled(size: ChunkSize, id: BlockId) -> Self {
        let mut chunk = DenseChunk {
            size,
            voxels: vec![id; size.volume()],
            columns: vec![0; size.columns()],
            non_air: 0,
        };
        chunk.set_all_masks(id);
        chunk
    }

    /// Takes ownership of `voxels` (x fastest, `edge^3` long) and computes the masks.
    pub fn from_voxels(size: ChunkSize, voxels: Vec<BlockId>) -> Result<Self, StorageError> {
        if voxels.len() != size.volume() {
            return Err(StorageError::WrongLength {
                expected: size.volume(),
                got: voxels.len(),
            });
        }
        let mut chunk = DenseChunk {
            size,
            voxels,
            columns: vec![0; size.columns()],
            non_air: 0,
        };
        chunk.recount();
        Ok(chunk)
    }

    /// A chunk whose voxel at each position is `f(position)`, called in linear order.
    pub fn from_fn(size: ChunkSize, mut f: impl FnMut(LocalPos) -> BlockId) -> Self {
        let voxels = (0..size.volume()).map(|i| f(local_of(size, i))).collect();
        let mut chunk = DenseChunk {
            size,
            voxels,
            columns: vec![0; size.columns()],
            non_air: 0,
        };
        chunk.recount();
        chunk
    }

    /// A dense copy of any storage, read row by row.
    pub fn from_storage<S: VoxelStorage>(storage: &S) -> Self {
        let size = storage.size();
        let e = size.edge_usize();
        let mut voxels = vec![BlockId::AIR; size.volume()];
        for (c, row) in voxels.chunks_exact_mut(e).enumerate() {
            let (y, z) = ((c % e) as u32, (c / e) as u32);
            if storage.copy_row(y, z, row).is_err() {
                // Unreachable for a storage that honours its own size; keep the row air.
                row.fill(BlockId::AIR);
            }
        }
        let mut chunk = DenseChunk {
            size,
            voxels,
            columns: vec![0; size.columns()],
            non_air: 0,
        };
        chunk.recount();
        chunk
    }

    /// A dense copy of a palette chunk.
    pub fn from_palette(palette: &PaletteChunk) -> Self {
        Self::from_storage(palette)
    }

    /// The voxels, x fastest: index with [`ChunkSize::linearize`].
    #[inline]
    pub fn as_slice(&self) -> &[BlockId] {
        &self.voxels
    }

    /// The occupancy masks, one per x-row, in [`ChunkSize::column_index`] order.
    #[inline]
    pub fn columns(&self) -> &[u64] {
        &self.columns
    }

    /// The voxel array, giving up the masks.
    pub fn into_voxels(self) -> Vec<BlockId> {
        self.voxels
    }

    fn set_all_masks(&mut self, id: BlockId) {
        let full = if id.is_air() {
            0
        } else {
            low_bits(self.size.edge_usize())
        };
        self.columns.fill(full);
        self.non_air = if id.is_air() { 0 } else { self.size.volume() };
    }

    /// Recomputes every mask and the count from the voxels.
    fn recount(&mut self) {
        let e = self.size.edge_usize();
        let mut non_air = 0;
        for (mask, row) in self.columns.iter_mut().zip(self.voxels.chunks_exact(e)) {
            *mask = row_mask(row);
            non_air += mask.count_ones() as usize;
        }
        self.non_air = non_air;
    }
}

impl VoxelStorage for DenseChunk {
    fn new_air(size: ChunkSize) -> Self {
        DenseChunk::new(size)
    }

    #[inline]
    fn size(&self) -> ChunkSize {
        self.size
    }

    #[inline]
    fn get(&self, pos: LocalPos) -> Result<BlockId, CoordError> {
        Ok(self.voxels[pos.index(self.size)?])
    }

    fn set(&mut self, pos: LocalPos, id: BlockId) -> Result<BlockId, CoordError> {
        let i = pos.index(self.size)?;
        let old = core::mem::replace(&mut self.voxels[i], id);
        if old.is_air() != id.is_air() {
            let bit = 1u64 << pos.x;
            let mask = &mut self.columns[self.size.column_index(pos.y.into(), pos.z.into())];
            if id.is_air() {
                *mask &= !bit;
                self.non_air -= 1;
            } else {
                *mask |= bit;
                self.non_air += 1;
            }
        }
        Ok(old)
    }

    fn fill(&mut self, id: BlockId) {
        self.voxels.fill(id);
        self.set_all_masks(id);
    }

    #[inline]
    fn non_air_count(&self) -> usize {
        self.non_air
    }

    #[inline]
    fn column_mask(&self, y: u32, z: u32) -> Result<u64, CoordError> {
        row_start(self.size, y, z)?;
        Ok(self.columns[self.size.column_index(y, z)])
    }

    #[inline]
    fn copy_row(&self, y: u32, z: u32, out: &mut [BlockId]) -> Result<(), StorageError> {
        let start = row_start(self.size, y, z)?;
        let e = self.size.edge_usize();
        if out.len() != e {
            return Err(StorageError::WrongLength {
                expected: e,
                got: out.len(),
            });
        }
        out.copy_from_slice(&self.voxels[start..start + e]);
        Ok(())
    }

    fn iter(&self) -> impl Iterator<Item = (LocalPos, BlockId)> + '_ {
        let size = self.size;
        self.voxels
            .iter()
            .enumerate()
            .map(move |(i, &id)| (local_of(size, i), id))
    }

    /// `Some(AIR)` for a chunk with no solid voxel (known from the count); `None` otherwise.
    #[inline]
    fn uniform(&self) -> Option<BlockId> {
        (self.non_air == 0).then_some(BlockId::AIR)
    }

    fn heap_bytes(&self) -> usize {
        self.voxels.capacity() * size_of::<BlockId>() + self.columns.capacity() * size_of::<u64>()
    }
}

impl From<&PaletteChunk> for DenseChunk {
    fn from(value: &PaletteChunk) -> Self {
        DenseChunk::from_palette(value)
    }
}
