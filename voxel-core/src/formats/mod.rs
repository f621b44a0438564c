//! Packed GPU formats: the contract between the CPU core and the GPU backend.
//!
//! | format                 | size  | what it is                                              |
//! | ---------------------- | ----- | ------------------------------------------------------- |
//! | [`DrawBlock`]          | 4 B   | one surface block: flags, 4-bit position, block id      |
//! | [`PackedQuad`]         | 8 B   | one greedy quad, expanded to 4 corners on the GPU       |
//! | [`ShellRun`]           | 8 B   | a box of vertical runs (shells, heightmap cubes)        |
//! | [`BlockVertex`]        | 16 B  | one quantized vertex (position, normal, uv, block)      |
//! | [`ClutterUnit`]        | 20 B  | one clutter instance                                    |
//! | [`ChunkDrawInfo`]      | 24 B  | a loaded chunk as the cull pass sees it                 |
//! | [`MeshedChunkInfo`]    | 112 B | a meshed chunk's bounds and layer ranges                |
//! | [`ChunkDrawIndirect`]  | 32 B  | one indexed indirect draw plus its chunk                |
//! | [compact quad]         | 6 B   | one smooth-mesh quad: 4 vertex indices as `[u16; 3]`    |
//!
//! [`ChunkLayersData`] is one chunk's packed layers as the backend uploads them, grouped by
//! [`DataKind`] (one gigabuffer per kind).
//!
//! [`SmoothQuads`] is a smooth mesh's quad buffer in one of three forms (compact records,
//! 4 x `u16`, 4 x `u32`), tagged by [`SmoothQuadForm`] for the GPU.
//!
//! Each format is a `#[repr(C)]` [`bytemuck::Pod`] struct whose docs give the bit layout, with
//! a size pinned at compile time, and a `...Fields` struct of plain values. `encode` checks
//! every field and names the one that does not fit ([`FormatError`]); `decode` accepts any bit
//! pattern and returns the fields or an error, never panicking. Where some bit patterns are
//! invalid (reserved bits, out-of-range enums and sentinels, non-finite floats), `decode`
//! rejects exactly what `encode` cannot produce, so the two are inverse on valid values.
//! Formats whose every bit pattern is valid decode infallibly. [`BlockVertex`] and
//! [`ClutterUnit`] quantize (see [`quantize`] and [`octahedral`] for the stated error bounds).
//!
//! Byte images assume a little-endian host, as on every wgpu target: WGSL reads two `u16`
//! fields as one `u32` with the first field in the low half.
//!
//! Every format has a WGSL twin in [`FORMATS_WGSL`], and a `WGSL_LAYOUT` table that a test
//! checks against naga's reflection of that source.
//!
//! The [compact quad] is the exception to the struct rule: a plain `[u16; 3]` record, since a
//! 6-byte stride is what makes it small and no WGSL struct can have it (shaders read it from
//! an `array<u32>`, as its docs show). It has [`compact_quad_encode`] and
//! [`compact_quad_decode`] instead of a `Fields` struct.
//!
//! [compact quad]: compact_quad
//!
//! ```
//! use voxel_core::BlockId;
//! use voxel_core::formats::{FaceDirection, PackedQuad, PackedQuadFields};
//!
//! let fields = PackedQuadFields {
//!     position: [3, 0, 5],
//!     width: 4,
//!     height: 2,
//!     face: FaceDirection::PosY,
//!     ao: [3, 3, 2, 0],
//!     block: BlockId(7),
//! };
//! let quad = PackedQuad::encode(&fields)?;
//! assert_eq!(quad.decode()?, fields);
//! // The top face of voxel (3, 0, 5) lies at y = 1.
//! assert_eq!(fields.corners()[0], [3, 1, 5]);
//! # Ok::<(), voxel_core::formats::FormatError>(())
//! ```

mod block_vertex;
mod chunk_draw_indirect;
mod chunk_draw_info;
mod chunk_layers;
mod clutter_unit;
pub mod compact_quad;
mod draw_block;
mod error;
mod face_direction;
mod layer_range;
mod meshed_chunk_info;
pub mod octahedral;
mod packed_quad;
pub mod quantize;
mod shell_run;
mod smooth_quads;
mod wgsl;

pub use block_vertex::{BlockVertex, BlockVertexFields};
pub use chunk_draw_indirect::{ChunkDrawIndirect, ChunkDrawIndirectFields};
pub use chunk_draw_info::{ChunkDrawInfo, ChunkDrawInfoFields, ChunkKind};
pub use chunk_layers::{ChunkLayersData, DataKind, PerKind};
pub use clutter_unit::{ClutterUnit, ClutterUnitFields};
pub use compact_quad::{
    COMPACT_QUAD_BYTES, COMPACT_QUAD_MAX_DELTA, compact_quad_decode, compact_quad_encode,
};
pub use draw_block::{DrawBlock, DrawBlockFields, DrawBlockFlags};
pub use error::FormatError;
pub use face_direction::FaceDirection;
pub use layer_range::{FaceLayerRange, LayerRange};
pub use meshed_chunk_info::{MeshedChunkInfo, MeshedChunkInfoFields};
pub use octahedral::{
    OCT16_MAX_ERROR_DEGREES, OCT32_MAX_ERROR_DEGREES, oct16_decode, oct16_encode, oct32_decode,
    oct32_encode,
};
pub use packed_quad::{PackedQuad, PackedQuadFields};
pub use quantize::UnormExtent;
pub use shell_run::{ShellRun, ShellRunFields};
pub use smooth_quads::{SmoothQuadForm, SmoothQuads};
pub use wgsl::{ALL_WGSL_STRUCTS, FORMATS_WGSL, WgslMember, WgslStruct, WgslType};
