//! [`WorldMap`]: chunks of one size by chunk coordinate.

use hashbrown::HashMap;

use crate::{BlockId, ChunkCoord, ChunkSize, WorldPos};

use super::{PaletteChunk, StorageError, VoxelStorage};

/// Chunks of one fixed [`ChunkSize`], keyed by [`ChunkCoord`].
///
/// A missing chunk reads as air. [`set_block`](WorldMap::set_block) creates a chunk only when it
/// writes something other than air there, so clearing empty space allocates nothing.
///
/// ```
/// use voxel_core::{BlockId, ChunkCoord, ChunkSize, WorldPos};
/// use voxel_core::storage::WorldMap;
///
/// let mut world: WorldMap = WorldMap::new(ChunkSize::S16);
/// let far = WorldPos::new(i32::MIN, i32::MAX, -1);
/// assert_eq!(world.set_block(far, BlockId(2)), BlockId::AIR);
/// assert_eq!(world.get_block(far), BlockId(2));
/// assert_eq!(world.len(), 1);
/// world.set_block(WorldPos::new(5, 5, 5), BlockId::AIR); // no chunk there: nothing allocated
/// assert_eq!(world.len(), 1);
/// ```
#[derive(Clone, Debug)]
pub struct WorldMap<C: VoxelStorage = PaletteChunk> {
    size: ChunkSize,
    chunks: HashMap<ChunkCoord, C>,
}

impl<C: VoxelStorage> WorldMap<C> {
    /// An empty world of chunks of `size`.
    pub fn new(size: ChunkSize) -> Self {
        WorldMap {
            size,
            chunks: HashMap::new(),
        }
    }

    /// The size every chunk of this world has.
    #[inline]
    pub fn size(&self) -> ChunkSize {
        self.size
    }

    /// Stores `chunk` at `coord` and returns the chunk it replaced. A chunk of another size is
    /// refused with [`StorageError::SizeMismatch`] (and dropped).
    pub fn insert(&mut self, coord: ChunkCoord, chunk: C) -> Result<Option<C>, StorageError> {
        if chunk.size() != self.size {
            return Err(StorageError::SizeMismatch {
                expected: self.size,
                got: chunk.size(),
            });
        }
        Ok(self.chunks.insert(coord, chunk))
    }

    /// The chunk at `coord`, if stored.
    #[inline]
    pub fn get(&self, coord: ChunkCoord) -> Option<&C> {
        self.chunks.get(&coord)
    }

    /// The chunk at `coord` for writing, if stored. (Writes through it keep its size.)
    #[inline]
    pub fn get_mut(&mut self, coord: ChunkCoord) -> Option<&mut C> {
        self.chunks.get_mut(&coord)
    }

    /// Removes and returns the chunk at `coord`.
    pub fn remove(&mut self, coord: ChunkCoord) -> Option<C> {
        self.chunks.remove(&coord)
    }

    /// Stored chunks.
    #[inline]
    pub fn len(&self) -> usize {
        self.chunks.len()
    }

    /// True when no chunk is stored.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.chunks.is_empty()
    }

    /// Every stored chunk with its coordinate, in no particular order.
    pub fn iter(&self) -> impl Iterator<Item = (ChunkCoord, &C)> + '_ {
        self.chunks.iter().map(|(&c, chunk)| (c, chunk))
    }

    /// The block at `pos`; air where no chunk is stored.
    pub fn get_block(&self, pos: WorldPos) -> BlockId {
        let (coord, local) = pos.split(self.size);
        self.chunks
            .get(&coord)
            .and_then(|c| c.get(local).ok())
            .unwrap_or(BlockId::AIR)
    }

    /// Writes `id` at `pos` and returns the block it replaced, creating the chunk when needed.
    /// Writing air where no chunk is stored allocates nothing.
    pub fn set_block(&mut self, pos: WorldPos, id: BlockId) -> BlockId {
        let (coord, local) = pos.split(self.size);
        if id.is_air() && !self.chunks.contains_key(&coord) {
            return BlockId::AIR;
        }
        let size = self.size;
        let chunk = self.chunks.entry(coord).or_insert_with(|| C::new_air(size));
        // `split` always yields a position inside a chunk of this world's size.
        chunk.set(local, id).unwrap_or(BlockId::AIR)
    }
}
