//! # voxel-scene
//!
//! Voxel scenes to mesh or show, shared by the viewer, the `voxmesh` command-line mesher and
//! the benchmarks:
//!
//! - [`terrain`]: the built-in procedural terrain (hills, caves, a sea), deterministic for a
//!   seed, as a chunk map ([`terrain_scene`], [`terrain_columns`]) or node by node at any
//!   level of detail, without bounds, for streaming ([`Terrain::fill_node`]);
//! - [`vox`]: a strict MagicaVoxel `.vox` loader: every model of the scene graph with its
//!   transforms, hidden nodes and layers left out, palette and materials, and a clear error
//!   for every malformed file;
//! - [`props`]: a strict glTF 2.0 loader for props (meshes drawn beside the voxels): meshes,
//!   materials with their base colour textures, the default scene flattened into placed
//!   meshes, a warning for every feature left out and an error for every malformed file;
//! - [`detailed`]: dense, detailed scenes for testing and benchmarking meshers (a Menger
//!   sponge, a foliage scene), cut into padded chunks of any size;
//! - [`rng`]: the small seeded generator those scenes and the benchmarks' inputs use.
//!
//! ```
//! use voxel_core::ChunkSize;
//! use voxel_scene::terrain_columns;
//!
//! let scene = terrain_columns(7, ChunkSize::S16, 24);
//! assert!(!scene.world.is_empty());
//! ```

pub mod detailed;
pub mod props;
pub mod rng;
pub mod terrain;
pub mod vox;

pub use terrain::{
    NodeContent, TERRAIN_TOP, Terrain, TerrainBlocks, TerrainScene, terrain_columns, terrain_scene,
};
