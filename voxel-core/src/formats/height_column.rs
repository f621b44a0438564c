//! `HeightColumn`: one terrain column of a heightmap tile in 64 bits.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};

use super::FormatError;
use super::error::check_max;
use super::wgsl::{WgslStruct, WgslType, member};
use crate::BlockId;

/// One column of a heightmap tile: its ground height and the two block ids its cube shows.
///
/// ```text
/// word  bits    field      meaning
/// 0     0..16   height     blocks of ground from the tile floor; 0 = no ground
/// 0     16..32  top id     the column's top opaque block (its top face and top side block)
/// 1     0..16   under id   the block below the top (the side faces below the top block)
/// 1     16..32  reserved   must be zero
/// ```
///
/// Only the reserved half of word 1 can be invalid, so [`HeightColumn::decode`] rejects exactly
/// what [`HeightColumn::encode`] cannot produce.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct HeightColumn {
    /// Height in the low half, top block id in the high half.
    pub height_top: u32,
    /// Under block id in the low half; the high half is reserved.
    pub under: u32,
}

const _: () = assert!(
    size_of::<HeightColumn>() == 8,
    "HeightColumn must be 8 bytes"
);

/// The unpacked fields of a [`HeightColumn`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct HeightColumnFields {
    /// Ground height in blocks, `0..=`[`HeightColumn::MAX_HEIGHT`].
    pub height: u32,
    /// The top opaque block.
    pub top: BlockId,
    /// The block below the top one (equal to `top` where the column is one block tall).
    pub under: BlockId,
}

impl HeightColumn {
    /// Largest encodable height.
    pub const MAX_HEIGHT: u32 = 0xFFFF;

    /// The WGSL struct `HeightColumn { height_top: u32, under: u32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "HeightColumn",
        size: size_of::<HeightColumn>(),
        members: &[
            member(
                "height_top",
                offset_of!(HeightColumn, height_top),
                WgslType::U32,
            ),
            member("under", offset_of!(HeightColumn, under), WgslType::U32),
        ],
    };

    /// Packs `fields`; fails with [`FormatError::IntegerOutOfRange`] naming
    /// `"HeightColumn.height"` if the height is above [`HeightColumn::MAX_HEIGHT`].
    pub fn encode(fields: &HeightColumnFields) -> Result<HeightColumn, FormatError> {
        let height = check_max("HeightColumn.height", fields.height, Self::MAX_HEIGHT)?;
        Ok(HeightColumn {
            height_top: height | (u32::from(fields.top.0) << 16),
            under: u32::from(fields.under.0),
        })
    }

    /// Unpacks the fields; fails with [`FormatError::ReservedBitsSet`] if the reserved half of
    /// word 1 is not zero.
    pub fn decode(self) -> Result<HeightColumnFields, FormatError> {
        let reserved = self.under & 0xFFFF_0000;
        if reserved != 0 {
            return Err(FormatError::ReservedBitsSet {
                field: "HeightColumn.under",
                bits: reserved,
            });
        }
        Ok(HeightColumnFields {
            height: self.height_top & 0xFFFF,
            top: BlockId((self.height_top >> 16) as u16),
            under: BlockId(self.under as u16),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_rejects_bad_input() {
        let fields = HeightColumnFields {
            height: 70,
            top: BlockId(3),
            under: BlockId(2),
        };
        let column = HeightColumn::encode(&fields).unwrap();
        assert_eq!(column.decode().unwrap(), fields);
        let too_high = HeightColumnFields {
            height: HeightColumn::MAX_HEIGHT + 1,
            ..fields
        };
        assert!(matches!(
            HeightColumn::encode(&too_high),
            Err(FormatError::IntegerOutOfRange {
                field: "HeightColumn.height",
                ..
            })
        ));
        let reserved = HeightColumn {
            under: column.under | 1 << 16,
            ..column
        };
        assert!(matches!(
            reserved.decode(),
            Err(FormatError::ReservedBitsSet { .. })
        ));
    }
}
