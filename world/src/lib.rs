//! An editable, persistent voxel world over a base (the procedural terrain, a function, or
//! air): block, box and sphere [`Edit`]s, the [`DirtySet`] each batch leaves at every level of
//! detail, the level-of-detail nodes rebuilt from the edited data, and crash-safe region files.
//!
//! | module | job |
//! | --- | --- |
//! | [`base`] | [`Base`]: what the world holds where nothing is edited |
//! | [`edit`] | [`Edit`] shapes, checked before anything is written |
//! | [`coarse`] | the base's own levels of detail with the edits downsampled into them |
//! | [`dirty`] | [`DirtySet`]: the nodes a batch invalidates, each once |
//! | [`world`] | [`World`]: materialized chunks, edits, level-of-detail rebuilds |
//! | [`region`] | the region file format (header, version, per-chunk checksums) |
//! | [`save`] | atomic saves of a world folder and loads that refuse bad files by name |
//!
//! The loop a renderer runs (the mesher alone, `examples/edit_remesh.rs`):
//!
//! ```
//! use mesher::{BlockClasses, ChunkMesh, ChunkMesher, MeshSettings};
//! use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk, WorldPos};
//! use voxel_world::{Edit, FnBase, World};
//!
//! let mut palette = MaterialPalette::new();
//! let stone = palette.push(Material::opaque(120, 120, 120)).unwrap();
//! let ground = FnBase(move |p: WorldPos| if p.y < 4 { stone } else { BlockId::AIR });
//! let mut world = World::new(ground, ChunkSize::S16, 2).unwrap();
//! let dirty = world
//!     .apply(&[Edit::Block { pos: WorldPos::new(0, 3, 0), id: BlockId::AIR }])
//!     .unwrap();
//! // The block sits at a corner of chunk (0, 0, 0) on x and z: four chunks share its faces.
//! assert_eq!(dirty.remesh(0).count(), 4);
//! let classes = BlockClasses::from_palette(&palette);
//! let (mut padded, mut mesher, mut mesh) = (PaddedChunk::new(ChunkSize::S16), ChunkMesher::new(), ChunkMesh::default());
//! for coord in dirty.remesh(0) {
//!     world.gather_chunk(coord, &mut padded).unwrap();
//!     mesher.mesh_gathered(&padded, coord, &classes, &MeshSettings::default(), &mut mesh).unwrap();
//!     // upload mesh.layers() for `coord`, replacing its old mesh
//! }
//! ```
//!
//! The crate sits beside `voxel-core` rather than inside it: it needs `std` (files, `fsync`),
//! the mesher's downsampling rule for the levels of detail and the terrain as a base, and
//! `voxel-core` stays `no_std` with no dependency on either.

pub mod base;
pub mod coarse;
pub mod dirty;
pub mod edit;
mod error;
pub mod region;
pub mod save;
pub mod world;

pub use base::{AirBase, Base, FnBase};
pub use dirty::{DirtySet, NodeKey};
pub use edit::{Edit, EditError, MAX_EDIT_VOXELS};
pub use error::WorldError;
pub use region::{
    ChunkFault, ChunkFaultKind, Region, RegionFormatError, decode_region, encode_region,
};
pub use save::{LoadReport, WORLD_FILE, write_atomic};
pub use world::{MAX_LEVEL, World};
