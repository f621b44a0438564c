//! `BlockVertex`: one quantized mesh vertex in 16 bytes.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use super::FormatError;
use super::octahedral::{oct16_decode, oct16_encode_field};
use super::quantize::{
    UnormExtent, unorm16x2_decode, unorm16x2_encode_field, unorm16x3_decode, unorm16x3_encode_field,
};
use super::wgsl::{WgslStruct, WgslType, member};
use crate::BlockId;

/// One vertex of a smooth (or otherwise non-quad) mesh, quantized to 16 bytes (Project
/// Ascendant's vertex format).
///
/// ```text
/// byte 0        2        4        6        8        10       12       14       16
///      +--------+--------+--------+--------+--------+--------+--------+--------+
///      |  pos x |  pos y |  pos z | normal |  uv u  |  uv v  | block  | extra  |
///      +--------+--------+--------+--------+--------+--------+--------+--------+
/// ```
///
/// | bytes  | field      | encoding                                                        |
/// | ------ | ---------- | --------------------------------------------------------------- |
/// | 0..6   | `position` | 3 x unorm16 over `0..=extent`, chunk-local (see [`quantize`])   |
/// | 6..8   | `normal`   | octahedral 8+8 bits (see [`octahedral`]); decodes to unit length |
/// | 8..12  | `uv`       | 2 x unorm16 over `0..=1`                                        |
/// | 12..14 | `block`    | [`BlockId`]                                                     |
/// | 14..16 | `extra`    | free for the mesher (e.g. packed light or AO); not interpreted  |
///
/// The position extent is not stored: encoder and decoder must agree on it (usually
/// [`UnormExtent::padded_chunk`] of the chunk size, with positions shifted by +1 so the apron
/// at -1 fits). Every bit pattern decodes.
///
/// WGSL reads the 16 bytes as 4 `u32` words; `u16` fields pair up little-endian
/// (`position_xy = x | y << 16`, `position_z_normal = z | normal << 16`, `uv = u | v << 16`,
/// `block_extra = block | extra << 16`).
///
/// [`quantize`]: super::quantize
/// [`octahedral`]: super::octahedral
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct BlockVertex {
    /// Unorm16 position codes, x, y, z.
    pub position: [u16; 3],
    /// Octahedral 8+8 normal code.
    pub normal: u16,
    /// Unorm16 texture coordinate codes, u, v.
    pub uv: [u16; 2],
    /// Block type.
    pub block: u16,
    /// Free 16 bits.
    pub extra: u16,
}

const _: () = assert!(
    size_of::<BlockVertex>() == 16,
    "BlockVertex must be 16 bytes"
);

/// The unpacked fields of a [`BlockVertex`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockVertexFields {
    /// Chunk-local position, each axis in `0.0..=extent`.
    pub position: Vec3,
    /// Surface normal: any finite non-zero vector (length is ignored); decodes to unit length.
    pub normal: Vec3,
    /// Texture coordinates, each in `0.0..=1.0`.
    pub uv: Vec2,
    /// Block type.
    pub block: BlockId,
    /// Free 16 bits, stored as is.
    pub extra: u16,
}

impl BlockVertex {
    /// The WGSL struct `BlockVertex { position_xy, position_z_normal, uv, block_extra: u32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "BlockVertex",
        size: size_of::<BlockVertex>(),
        members: &[
            member(
                "position_xy",
                offset_of!(BlockVertex, position),
                WgslType::U32,
            ),
            member(
                "position_z_normal",
                offset_of!(BlockVertex, position) + 2 * size_of::<u16>(),
                WgslType::U32,
            ),
            member("uv", offset_of!(BlockVertex, uv), WgslType::U32),
            member("block_extra", offset_of!(BlockVertex, block), WgslType::U32),
        ],
    };

    /// Quantizes `fields` with the position `extent`.
    ///
    /// Fails with [`FormatError::QuantizeOutOfRange`] for a position axis outside
    /// `0..=extent` (field `"BlockVertex.position"`) or a uv outside `0..=1`
    /// (`"BlockVertex.uv"`), and with [`FormatError::InvalidNormal`] for a NaN, infinite or zero
    /// normal (`"BlockVertex.normal"`).
    pub fn encode(
        fields: &BlockVertexFields,
        extent: UnormExtent,
    ) -> Result<BlockVertex, FormatError> {
        Ok(BlockVertex {
            position: unorm16x3_encode_field(fields.position, extent, "BlockVertex.position")?,
            normal: oct16_encode_field(fields.normal, "BlockVertex.normal")?,
            uv: unorm16x2_encode_field(fields.uv, "BlockVertex.uv")?,
            block: fields.block.0,
            extra: fields.extra,
        })
    }

    /// Unpacks the fields with the position `extent`. Every bit pattern is valid; the normal is
    /// always unit length.
    pub fn decode(self, extent: UnormExtent) -> BlockVertexFields {
        BlockVertexFields {
            position: unorm16x3_decode(self.position, extent),
            normal: oct16_decode(self.normal),
            uv: unorm16x2_decode(self.uv),
            block: BlockId(self.block),
            extra: self.extra,
        }
    }
}
