//! `DrawBlock`: one surface block of a chunk in 32 bits.

use core::mem::{offset_of, size_of};
use core::ops::{BitOr, BitOrAssign};

use bytemuck::{Pod, Zeroable};

use super::FormatError;
use super::error::check_max;
use super::wgsl::{WgslStruct, WgslType, member};
use crate::BlockId;

/// The 4 flag bits of a [`DrawBlock`].
///
/// | bit | flag          | meaning                                                        |
/// | --- | ------------- | -------------------------------------------------------------- |
/// | 0   | `TRANSPARENT` | drawn in the transparent pass (water, glass)                   |
/// | 1   | `EMISSIVE`    | emits light; the lighting pass adds its material's emission    |
/// | 2   | `SMOOTH`      | part of a smooth (SurfaceNets) surface, not drawn as a cube    |
/// | 3   | `HAS_CLUTTER` | carries clutter (grass, pebbles) on its top face               |
///
/// Only these 4 bits exist: [`DrawBlockFlags::from_bits`] rejects anything above `0b1111`, so
/// every `DrawBlockFlags` value fits the packed field.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DrawBlockFlags(u8);

impl DrawBlockFlags {
    /// No flag set: an opaque, non-emissive cube without clutter.
    pub const EMPTY: DrawBlockFlags = DrawBlockFlags(0);
    /// Bit 0: drawn in the transparent pass.
    pub const TRANSPARENT: DrawBlockFlags = DrawBlockFlags(1 << 0);
    /// Bit 1: emits light.
    pub const EMISSIVE: DrawBlockFlags = DrawBlockFlags(1 << 1);
    /// Bit 2: part of a smooth surface.
    pub const SMOOTH: DrawBlockFlags = DrawBlockFlags(1 << 2);
    /// Bit 3: carries clutter.
    pub const HAS_CLUTTER: DrawBlockFlags = DrawBlockFlags(1 << 3);
    /// Every flag bit.
    pub const ALL: DrawBlockFlags = DrawBlockFlags(0b1111);

    /// The flags with these bits, or [`FormatError::IntegerOutOfRange`] if a bit above bit 3 is
    /// set.
    pub fn from_bits(bits: u8) -> Result<DrawBlockFlags, FormatError> {
        check_max("DrawBlock.flags", bits.into(), Self::ALL.0.into())?;
        Ok(DrawBlockFlags(bits))
    }

    /// The raw bits, `0..16`.
    #[inline]
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// True if every flag of `other` is set in `self`.
    #[inline]
    pub const fn contains(self, other: DrawBlockFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// The flags of both.
    #[inline]
    pub const fn union(self, other: DrawBlockFlags) -> DrawBlockFlags {
        DrawBlockFlags(self.0 | other.0)
    }
}

impl BitOr for DrawBlockFlags {
    type Output = DrawBlockFlags;
    fn bitor(self, rhs: DrawBlockFlags) -> DrawBlockFlags {
        self.union(rhs)
    }
}

impl BitOrAssign for DrawBlockFlags {
    fn bitor_assign(&mut self, rhs: DrawBlockFlags) {
        *self = self.union(rhs);
    }
}

/// One surface block of a chunk, packed into one `u32` (Project Ascendant's DrawBlock list).
///
/// ```text
/// bit  0        4        8        12       16                               32
///      +--------+--------+--------+--------+--------------------------------+
///      | flags  |   x    |   y    |   z    |            block id            |
///      +--------+--------+--------+--------+--------------------------------+
/// ```
///
/// | bits   | field    | range    | meaning                                   |
/// | ------ | -------- | -------- | ----------------------------------------- |
/// | 0..4   | flags    | 0..16    | [`DrawBlockFlags`]                        |
/// | 4..8   | x        | 0..16    | chunk-local position (chunks up to 16^3)  |
/// | 8..12  | y        | 0..16    |                                           |
/// | 12..16 | z        | 0..16    |                                           |
/// | 16..32 | block id | any u16  | [`BlockId`]                               |
///
/// Every bit pattern is valid, so [`DrawBlock::decode`] cannot fail.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct DrawBlock {
    /// The packed bits (layout above).
    pub bits: u32,
}

const _: () = assert!(size_of::<DrawBlock>() == 4, "DrawBlock must be 4 bytes");

/// The unpacked fields of a [`DrawBlock`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DrawBlockFields {
    /// Chunk-local position, each axis `0..16`.
    pub position: [u32; 3],
    /// Flags.
    pub flags: DrawBlockFlags,
    /// The block's type.
    pub block: BlockId,
}

impl DrawBlock {
    /// Largest valid position axis.
    pub const MAX_POSITION: u32 = 15;

    /// The WGSL struct `DrawBlock { bits: u32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "DrawBlock",
        size: size_of::<DrawBlock>(),
        members: &[member("bits", offset_of!(DrawBlock, bits), WgslType::U32)],
    };

    /// Packs `fields`; fails with [`FormatError::IntegerOutOfRange`] naming the axis
    /// (`"DrawBlock.position.x"` ...) if a position axis is above 15.
    pub fn encode(fields: &DrawBlockFields) -> Result<DrawBlock, FormatError> {
        const AXES: [&str; 3] = [
            "DrawBlock.position.x",
            "DrawBlock.position.y",
            "DrawBlock.position.z",
        ];
        let mut bits = u32::from(fields.flags.bits());
        for (axis, (&value, field)) in fields.position.iter().zip(AXES).enumerate() {
            bits |= check_max(field, value, Self::MAX_POSITION)? << (4 + 4 * axis);
        }
        bits |= u32::from(fields.block.0) << 16;
        Ok(DrawBlock { bits })
    }

    /// Unpacks the fields. Every bit pattern is valid.
    pub const fn decode(self) -> DrawBlockFields {
        let b = self.bits;
        DrawBlockFields {
            position: [(b >> 4) & 0xF, (b >> 8) & 0xF, (b >> 12) & 0xF],
            flags: DrawBlockFlags((b & 0xF) as u8),
            block: BlockId((b >> 16) as u16),
        }
    }
}
