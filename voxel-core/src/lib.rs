//! # voxel-core
//!
//! The foundation of the voxel meshing stack: block ids and materials, i32-safe world / chunk /
//! local coordinates, chunk storage (dense and palette-compressed, with per-column occupancy
//! masks), a world map with padded-neighbourhood gathers, a versioned chunk codec, and every packed
//! GPU format together with its WGSL twin.
//!
//! The crate is `#![no_std]` + `alloc`; the default `std` feature only adds
//! `std::error::Error` impls. It never names a GPU API: the formats are plain bytes
//! ([`bytemuck::Pod`]) that any backend can upload.
//!
//! Data flows one way: storage -> padded neighbourhood -> (the `mesher` crate) -> packed formats.
#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

mod block;
mod coords;
pub mod formats;
mod material;
mod size;
pub mod storage;

pub use block::BlockId;
pub use coords::{ChunkCoord, CoordError, LocalPos, WorldPos};
pub use formats::{FaceDirection, FormatError};
pub use material::{Material, MaterialClass, MaterialPalette, PaletteError};
pub use size::{ChunkSize, UnsupportedChunkSize};
pub use storage::{
    DenseChunk, PaddedChunk, PaletteChunk, StorageError, VoxelStorage, WorldMap,
    gather_neighbourhood,
};
