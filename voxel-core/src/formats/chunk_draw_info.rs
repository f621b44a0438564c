//! `ChunkDrawInfo`: what the GPU cull pass needs to know about one loaded chunk.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};

use super::FormatError;
use super::wgsl::{WgslStruct, WgslType, member};
use crate::ChunkCoord;

/// How a chunk is drawn.
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ChunkKind {
    /// Nothing to draw (air, or fully hidden interior).
    #[default]
    Empty = 0,
    /// Drawn from its meshed layers ([`MeshedChunkInfo`](super::MeshedChunkInfo)).
    Mesh = 1,
    /// Drawn far away as a raycast box sprite.
    Sprite = 2,
}

impl ChunkKind {
    /// Every kind, in value order.
    pub const ALL: [ChunkKind; 3] = [ChunkKind::Empty, ChunkKind::Mesh, ChunkKind::Sprite];

    /// The kind with this stored value, or [`FormatError::InvalidChunkKind`].
    pub const fn from_u32(value: u32) -> Result<ChunkKind, FormatError> {
        match value {
            0 => Ok(ChunkKind::Empty),
            1 => Ok(ChunkKind::Mesh),
            2 => Ok(ChunkKind::Sprite),
            value => Err(FormatError::InvalidChunkKind { value }),
        }
    }
}

/// One loaded chunk as the cull pass sees it, 24 bytes (Project Ascendant's ChunkDrawInfo).
///
/// | bytes  | field              | type | meaning                                               |
/// | ------ | ------------------ | ---- | ----------------------------------------------------- |
/// | 0..4   | `chunk[0]` (x)     | i32  | chunk coordinate; uploaded camera-relative, so the    |
/// | 4..8   | `chunk[1]` (y)     | i32  | GPU never sees a large world coordinate               |
/// | 8..12  | `chunk[2]` (z)     | i32  |                                                       |
/// | 12..16 | `kind`             | u32  | [`ChunkKind`]: 0, 1 or 2; others are errors           |
/// | 16..20 | `draw_count`       | i32  | `-1` = needs refresh, else `>= 0`; below -1 is an error |
/// | 20..24 | `gigabuffer_index` | i32  | `-1` = not resident, else `>= 0`; below -1 is an error  |
///
/// WGSL: `ChunkDrawInfo { chunk_x, chunk_y, chunk_z: i32, kind: u32, draw_count: i32,
/// gigabuffer_index: i32 }`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct ChunkDrawInfo {
    /// Chunk coordinate x, y, z.
    pub chunk: [i32; 3],
    /// [`ChunkKind`] value.
    pub kind: u32,
    /// Draw count, or -1 = needs refresh.
    pub draw_count: i32,
    /// Gigabuffer slot, or -1 = not resident.
    pub gigabuffer_index: i32,
}

const _: () = assert!(
    size_of::<ChunkDrawInfo>() == 24,
    "ChunkDrawInfo must be 24 bytes"
);

/// The unpacked fields of a [`ChunkDrawInfo`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ChunkDrawInfoFields {
    /// Chunk coordinate (camera-relative once uploaded).
    pub chunk: ChunkCoord,
    /// How the chunk is drawn.
    pub kind: ChunkKind,
    /// `None` = needs refresh (stored as -1); `Some(n)` with `n <= i32::MAX`.
    pub draw_count: Option<u32>,
    /// `None` = not resident (stored as -1); `Some(i)` with `i <= i32::MAX`.
    pub gigabuffer_index: Option<u32>,
}

/// Encodes an optional count as `-1` or a non-negative `i32`.
fn encode_sentinel(field: &'static str, value: Option<u32>) -> Result<i32, FormatError> {
    match value {
        None => Ok(-1),
        Some(v) => i32::try_from(v).map_err(|_| FormatError::IntegerOutOfRange {
            field,
            value: v.into(),
            min: 0,
            max: i32::MAX.into(),
        }),
    }
}

/// Decodes `-1` as `None` and `>= 0` as `Some`; anything below -1 is an error.
fn decode_sentinel(field: &'static str, value: i32) -> Result<Option<u32>, FormatError> {
    match value {
        -1 => Ok(None),
        v if v >= 0 => Ok(Some(v as u32)),
        v => Err(FormatError::IntegerOutOfRange {
            field,
            value: v.into(),
            min: -1,
            max: i32::MAX.into(),
        }),
    }
}

impl ChunkDrawInfo {
    /// The WGSL struct (member per row of the table above).
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "ChunkDrawInfo",
        size: size_of::<ChunkDrawInfo>(),
        members: &[
            member("chunk_x", offset_of!(ChunkDrawInfo, chunk), WgslType::I32),
            member(
                "chunk_y",
                offset_of!(ChunkDrawInfo, chunk) + 4,
                WgslType::I32,
            ),
            member(
                "chunk_z",
                offset_of!(ChunkDrawInfo, chunk) + 8,
                WgslType::I32,
            ),
            member("kind", offset_of!(ChunkDrawInfo, kind), WgslType::U32),
            member(
                "draw_count",
                offset_of!(ChunkDrawInfo, draw_count),
                WgslType::I32,
            ),
            member(
                "gigabuffer_index",
                offset_of!(ChunkDrawInfo, gigabuffer_index),
                WgslType::I32,
            ),
        ],
    };

    /// Packs `fields`; fails with [`FormatError::IntegerOutOfRange`] if a draw count or
    /// gigabuffer index is above `i32::MAX`.
    pub fn encode(fields: &ChunkDrawInfoFields) -> Result<ChunkDrawInfo, FormatError> {
        Ok(ChunkDrawInfo {
            chunk: [fields.chunk.x, fields.chunk.y, fields.chunk.z],
            kind: fields.kind as u32,
            draw_count: encode_sentinel("ChunkDrawInfo.draw_count", fields.draw_count)?,
            gigabuffer_index: encode_sentinel(
                "ChunkDrawInfo.gigabuffer_index",
                fields.gigabuffer_index,
            )?,
        })
    }

    /// Unpacks the fields, or fails with [`FormatError::InvalidChunkKind`] for a kind above 2
    /// and [`FormatError::IntegerOutOfRange`] for a draw count or index below -1.
    pub fn decode(self) -> Result<ChunkDrawInfoFields, FormatError> {
        let [x, y, z] = self.chunk;
        Ok(ChunkDrawInfoFields {
            chunk: ChunkCoord::new(x, y, z),
            kind: ChunkKind::from_u32(self.kind)?,
            draw_count: decode_sentinel("ChunkDrawInfo.draw_count", self.draw_count)?,
            gigabuffer_index: decode_sentinel(
                "ChunkDrawInfo.gigabuffer_index",
                self.gigabuffer_index,
            )?,
        })
    }
}
