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
//!
//! # Module map
//!
//! The greedy mesher's modules in the order the data flows through them, from a chunk's ids
//! to [`PackedQuad`](voxel_core::formats::PackedQuad)s (see [`GreedyMesher`] for the steps).
//! A step calls the steps after it and reads the types of those before it and of the leaves
//! listed below; no module imports one that imports it back (a test reads the sources and
//! checks).
//!
//! | step | module | what it does |
//! | ---- | ------ | ------------ |
//! | entry | `greedy` | [`GreedyMesher`]: the entry points, the per-instruction-set copies, and `mesh_chunk`, which runs the steps below for one chunk |
//! | 1 | `plain` | a plain padded `u16` array's occupancy columns ([`GreedyMesher::mesh_u16`] only; a `PaddedChunk` has its own) |
//! | 1 | `plain_x86` | the same columns with AVX2 kernels, for the x86-64-v3 copy of the mesher |
//! | 2 | `masks` | opaque and transparent bit masks in the three slice layouts, and the early exit for empty and buried chunks |
//! | 3 | `input` | `Input`: what the rest reads (ids, masks, options), built once per chunk |
//! | 4 | `lone_x` | a pre-pass with AO on, from 32^3 up: ±X faces with no neighbouring face, in rows of many, written straight from the occupancy rows (checkerboards) |
//! | 5 | `slices` | per direction and slice: the face lines (`cur & !front`), opaque then transparent, handed to `merge` |
//! | 6 | `merge` | per slice: keys (id + AO) of the faces, equal-key masks, the faces that merge with nothing written as 1 x 1 quads |
//! | 7 | `grow` | greedy quads grown from the equal-key masks, in `block-mesh`'s order |
//! | 7 | `line_units` | lines of faces that become 1 x 1 quads, keyed face by face, or in bulk for faces that share a key |
//! | out | `mesh` | [`BlockyMesh`]: the quads, opaque and transparent, per face direction |
//!
//! The leaves those steps share:
//!
//! | module | holds |
//! | ------ | ----- |
//! | `faces` | `SliceFaces`, one slice as the passes read it (ids, AO, quad words, id checks); `UnitLine`, the one encoder of 1 x 1 quads; and `Quads`, where its quads go |
//! | `direction` | `Axis<A>`: the slice, line and bit axes of an axis's faces and their `PackedQuad` shifts, as constants; `Facing`: which of the axis's two faces, read at run time (each axis's walk serves both) |
//! | `keys` | `Keys`, the greedy pass's scratch (keys and equal-key masks of one slice) |
//! | `memo` | `NeighbourhoodMemo`: the AO split of recent lines, for periodic slices |
//! | `one_id` | whether a chunk's voxels with a face share one id: then, with AO off, every face has one key and nothing is keyed (and whether any voxel has a face: with AO off a chunk with none ends there) |
//! | `equal` | `EqualIds`: with AO off, in chunks whose exposed rows are dense, every exposed voxel's id compared with its next neighbours' along x, y and z by SIMD row compares (built by the entry after step 2), as the equal-key masks of every slice: then nothing is keyed |
//! | `ao` | the AO rule, the per-direction AO tables, AO of a whole line as bit planes, the diagonal flip |
//! | `aligned` | `Slice`, 64 lines of one slice, and `Slices`, the masks' scratch slices, each on a cache line |
//! | `bits` | bit tools: row masks, the 64 x 64 transpose, `ones` (set bits), `masked` (indexes kept in range) |
//!
//! [`visible_faces`] (one quad per face) runs the same steps with merging off.

mod aligned;
pub mod ao;
mod bits;
mod direction;
mod equal;
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
mod one_id;
mod plain;
#[cfg(target_arch = "x86_64")]
mod plain_x86;
mod slices;
mod visible;

pub use ao::{corner_ao, triangle_indices};
pub use greedy::GreedyMesher;
pub use mesh::{BlockyLayer, BlockyMesh};
pub use visible::visible_faces;
