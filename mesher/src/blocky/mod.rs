//! Blocky meshers: one quad per visible face, and greedy quads with per-vertex ambient
//! occlusion, both emitting 8-byte [`PackedQuad`](voxel_core::formats::PackedQuad)s.
//!
//! | entry | what it does |
//! | ----- | ------------ |
//! | [`visible_faces`] / [`GreedyMesher::visible_faces`] | one quad per exposed face |
//! | [`GreedyMesher::mesh`] | greedy quads from a [`PaddedChunk`](voxel_core::PaddedChunk), starting from its occupancy columns |
//! | [`GreedyMesher::mesh_u16`] | the same from a plain padded `u16` array (masks built first) |
//! | [`triangle_indices`] | the AO-aware diagonal of a quad, mirrored by the shader |
//!
//! # Visibility
//!
//! Opaque blocks (classes `Opaque`, `ClutterBearing`, `Smoothable`) hide every face they
//! touch. Transparent blocks show faces against air and against other transparent ids, but not
//! between two voxels of the same id. An opaque face next to a transparent block is shown.
//! Opaque faces go to [`BlockyMesh::opaque`], transparent ones to [`BlockyMesh::transparent`].
//!
//! # Ambient occlusion
//!
//! Every quad carries 4 corner AO values (3 = unoccluded) from the opaque voxels of the layer in
//! front of it; see [`ao`] for the rule and the diagonal flip. Greedy quads merge only faces
//! whose ids and 4 corner values all agree, so merging never changes the shading.
//!
//! # Padding contract
//!
//! The input is a chunk plus a one-voxel border (see [`voxel_core::PaddedChunk`] and
//! [`voxel_core::gather_neighbourhood`]): faces are emitted for the chunk's voxels only, and the
//! border decides whether a face on the chunk's boundary is hidden and how its corners are
//! shaded. Quad positions are chunk-local
//! (padded coordinate - 1).

pub mod ao;
mod bits;
mod direction;
mod faces;
mod greedy;
mod grow;
mod input;
mod keys;
mod line_units;
mod lone_x;
mod masks;
mod memo;
mod merge;
mod mesh;
mod plain;
mod slices;
mod visible;
mod wide;

pub use ao::{corner_ao, triangle_indices};
pub use greedy::GreedyMesher;
pub use mesh::{BlockyLayer, BlockyMesh};
pub use visible::visible_faces;
