//! Chunk storage, the world map, neighbourhood gathers and the chunk codec.
//!
//! | item | job |
//! | --- | --- |
//! | [`VoxelStorage`] | the one interface both chunk storages share |
//! | [`DenseChunk`] | one [`BlockId`](crate::BlockId) per voxel plus stored per-row occupancy masks: fastest reads |
//! | [`PaletteChunk`] | palette-compressed (uniform, 1/2/4/8 bits per voxel, or raw 16-bit ids): smallest |
//! | [`WorldMap`] | chunks by [`ChunkCoord`](crate::ChunkCoord), block access by [`WorldPos`](crate::WorldPos) |
//! | [`PaddedChunk`], [`gather_neighbourhood`] | a chunk plus its one-voxel border, the input of every mesher |
//! | [`encode_chunk`], [`decode_chunk`] | the versioned binary form of one [`PaletteChunk`] |
//!
//! Everything checks its input and returns a named error ([`StorageError`], [`CodecError`],
//! [`CoordError`](crate::CoordError)); nothing here panics on bad positions, sizes or bytes.
//!
//! ```
//! use voxel_core::{BlockId, ChunkCoord, ChunkSize, WorldPos};
//! use voxel_core::storage::{gather_neighbourhood, PaddedChunk, WorldMap};
//!
//! let mut world: WorldMap = WorldMap::new(ChunkSize::S32);
//! world.set_block(WorldPos::new(-1, 0, 0), BlockId(7)); // last voxel of chunk (-1, 0, 0)
//! let mut padded = PaddedChunk::new(ChunkSize::S32);
//! gather_neighbourhood(&world, ChunkCoord::new(0, 0, 0), &mut padded);
//! // Chunk (0,0,0)'s voxel (0,0,0) sits at padded (1,1,1); its -x neighbour at padded (0,1,1).
//! assert_eq!(padded.get(0, 1, 1), Ok(BlockId(7)));
//! assert_eq!(padded.column(1, 1), Ok(0b1));
//! ```

pub mod codec;
mod dense;
mod error;
pub mod neighbourhood;
mod packed_bits;
mod palette;
mod palette_build;
mod palette_repr;
mod traits;
mod world;

pub use codec::{
    CODEC_VERSION, CodecError, HEADER_LEN, MAGIC, decode_chunk, encode_chunk, encoded_len,
};
pub use dense::DenseChunk;
pub use error::StorageError;
pub use neighbourhood::{PaddedChunk, gather_neighbourhood};
pub use palette::PaletteChunk;
pub use traits::VoxelStorage;
pub use world::WorldMap;
