//! `ChunkDrawIndirect`: one indexed indirect draw, tagged with its chunk.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};

use super::wgsl::{WgslStruct, WgslType, member};
use crate::ChunkCoord;

/// One draw written by the cull pass, 32 bytes: wgpu's `DrawIndexedIndirectArgs` (20 bytes, in
/// wgpu's order) followed by the chunk it draws.
///
/// | bytes  | field            | type    | meaning                                        |
/// | ------ | ---------------- | ------- | ---------------------------------------------- |
/// | 0..4   | `index_count`    | u32     | indices per instance                           |
/// | 4..8   | `instance_count` | u32     | instances (0 = culled)                         |
/// | 8..12  | `first_index`    | u32     | first index in the index buffer                |
/// | 12..16 | `base_vertex`    | i32     | added to each index                            |
/// | 16..20 | `first_instance` | u32     | first instance (non-zero needs wgpu's `INDIRECT_FIRST_INSTANCE`) |
/// | 20..32 | `chunk` x, y, z  | 3 x i32 | camera-relative chunk coordinate               |
///
/// Every bit pattern decodes. Note that wgpu's `multi_draw_indexed_indirect` reads records
/// 20 bytes apart; to draw from 32-byte records, issue one `draw_indexed_indirect` per record
/// (offset `32 * i`) or copy the args into a tightly packed buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct ChunkDrawIndirect {
    /// Indices per instance.
    pub index_count: u32,
    /// Instances to draw.
    pub instance_count: u32,
    /// First index in the index buffer.
    pub first_index: u32,
    /// Added to each index before fetching a vertex.
    pub base_vertex: i32,
    /// First instance.
    pub first_instance: u32,
    /// Camera-relative chunk coordinate x, y, z.
    pub chunk: [i32; 3],
}

const _: () = assert!(
    size_of::<ChunkDrawIndirect>() == 32,
    "ChunkDrawIndirect must be 32 bytes"
);
const _: () = assert!(
    offset_of!(ChunkDrawIndirect, chunk) == 20,
    "the chunk must follow the 20 bytes of DrawIndexedIndirectArgs"
);

/// The unpacked fields of a [`ChunkDrawIndirect`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ChunkDrawIndirectFields {
    /// Indices per instance.
    pub index_count: u32,
    /// Instances to draw.
    pub instance_count: u32,
    /// First index in the index buffer.
    pub first_index: u32,
    /// Added to each index before fetching a vertex.
    pub base_vertex: i32,
    /// First instance.
    pub first_instance: u32,
    /// Camera-relative chunk coordinate.
    pub chunk: ChunkCoord,
}

impl ChunkDrawIndirect {
    /// The WGSL struct `ChunkDrawIndirect { index_count, instance_count, first_index: u32,
    /// base_vertex: i32, first_instance: u32, chunk_x, chunk_y, chunk_z: i32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "ChunkDrawIndirect",
        size: size_of::<ChunkDrawIndirect>(),
        members: &[
            member(
                "index_count",
                offset_of!(ChunkDrawIndirect, index_count),
                WgslType::U32,
            ),
            member(
                "instance_count",
                offset_of!(ChunkDrawIndirect, instance_count),
                WgslType::U32,
            ),
            member(
                "first_index",
                offset_of!(ChunkDrawIndirect, first_index),
                WgslType::U32,
            ),
            member(
                "base_vertex",
                offset_of!(ChunkDrawIndirect, base_vertex),
                WgslType::I32,
            ),
            member(
                "first_instance",
                offset_of!(ChunkDrawIndirect, first_instance),
                WgslType::U32,
            ),
            member(
                "chunk_x",
                offset_of!(ChunkDrawIndirect, chunk),
                WgslType::I32,
            ),
            member(
                "chunk_y",
                offset_of!(ChunkDrawIndirect, chunk) + 4,
                WgslType::I32,
            ),
            member(
                "chunk_z",
                offset_of!(ChunkDrawIndirect, chunk) + 8,
                WgslType::I32,
            ),
        ],
    };

    /// Packs `fields`. Every value fits.
    pub const fn encode(fields: &ChunkDrawIndirectFields) -> ChunkDrawIndirect {
        ChunkDrawIndirect {
            index_count: fields.index_count,
            instance_count: fields.instance_count,
            first_index: fields.first_index,
            base_vertex: fields.base_vertex,
            first_instance: fields.first_instance,
            chunk: [fields.chunk.x, fields.chunk.y, fields.chunk.z],
        }
    }

    /// Unpacks the fields. Every bit pattern is valid.
    pub const fn decode(self) -> ChunkDrawIndirectFields {
        let [x, y, z] = self.chunk;
        ChunkDrawIndirectFields {
            index_count: self.index_count,
            instance_count: self.instance_count,
            first_index: self.first_index,
            base_vertex: self.base_vertex,
            first_instance: self.first_instance,
            chunk: ChunkCoord::new(x, y, z),
        }
    }
}
