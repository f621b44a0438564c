//! `PackedQuad`: one greedy-meshed quad in 8 bytes, expanded to 4 corners on the GPU.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};

use super::error::{check_max, check_range, check_reserved};
use super::wgsl::{WgslStruct, WgslType, member};
use super::{FaceDirection, FormatError};
use crate::BlockId;

/// One greedy quad, packed into two `u32` words (WGSL has no `u64`).
///
/// The vertex shader expands it into 4 corners with `packed_quad_corner` (the twin of
/// [`PackedQuadFields::corners`]), so a chunk's opaque layer costs 8 bytes per quad instead of
/// 4 vertices.
///
/// Word 0, `position_size`:
///
/// ```text
/// bit  0      6      12     18          24          30  32
///      +------+------+------+-----------+-----------+---+
///      |  x   |  y   |  z   | width - 1 | height - 1| 0 |
///      +------+------+------+-----------+-----------+---+
/// ```
///
/// Word 1, `face_ao_block`:
///
/// ```text
/// bit  0      3                      11                               27      32
///      +------+----+----+----+----+--------------------------------+-------+
///      | face |ao0 |ao1 |ao2 |ao3 |            block id            |   0   |
///      +------+----+----+----+----+--------------------------------+-------+
/// ```
///
/// | word | bits   | field      | range  | meaning                                           |
/// | ---- | ------ | ---------- | ------ | ------------------------------------------------- |
/// | 0    | 0..6   | x          | 0..64  | chunk-local position of the voxel whose face this |
/// | 0    | 6..12  | y          | 0..64  | is (of the quad's first voxel, at corner 0)       |
/// | 0    | 12..18 | z          | 0..64  |                                                   |
/// | 0    | 18..24 | width - 1  | 0..64  | width 1..=64 voxels, along the face's width axis  |
/// | 0    | 24..30 | height - 1 | 0..64  | height 1..=64 voxels, along the height axis       |
/// | 0    | 30..32 | reserved   | 0      | must be zero                                      |
/// | 1    | 0..3   | face       | 0..6   | [`FaceDirection`] index; 6 and 7 are errors       |
/// | 1    | 3..11  | ao         | 4 x 0..4 | ambient occlusion of corner i at bits 3+2i..5+2i |
/// | 1    | 11..27 | block id   | u16    | [`BlockId`]                                       |
/// | 1    | 27..32 | reserved   | 0      | must be zero                                      |
///
/// Width and height run along the face's [`width_axis`](FaceDirection::width_axis) and
/// [`height_axis`](FaceDirection::height_axis): z and y for ±X faces, x and z for ±Y, x and y
/// for ±Z.
///
/// Ambient occlusion per corner: `3` = unoccluded (full light), `0` = most occluded (both side
/// neighbours and the corner neighbour solid). The corner order is that of
/// [`PackedQuadFields::corners`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct PackedQuad {
    /// Word 0: position, width - 1, height - 1 (layout above).
    pub position_size: u32,
    /// Word 1: face direction, per-corner AO, block id (layout above).
    pub face_ao_block: u32,
}

const _: () = assert!(size_of::<PackedQuad>() == 8, "PackedQuad must be 8 bytes");

/// The unpacked fields of a [`PackedQuad`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PackedQuadFields {
    /// Chunk-local position of the voxel that owns corner 0 of the face, each axis `0..64`.
    pub position: [u32; 3],
    /// Size along the face's width axis in voxels, `1..=64`.
    pub width: u32,
    /// Size along the face's height axis in voxels, `1..=64`.
    pub height: u32,
    /// Which way the face points.
    pub face: FaceDirection,
    /// Ambient occlusion per corner (order of [`corners`](Self::corners)), `0..=3`,
    /// 3 = unoccluded.
    pub ao: [u8; 4],
    /// The block type the quad shows.
    pub block: BlockId,
}

/// Word 0 bits that must be zero: those past `height - 1`.
const WORD0_RESERVED: u32 = !0 << (PackedQuad::HEIGHT_SHIFT + PackedQuad::FIELD_BITS);
/// Word 1 bits that must be zero: those past the block id.
const WORD1_RESERVED: u32 = !0 << (PackedQuad::BLOCK_SHIFT + 16);

impl PackedQuad {
    /// Largest valid position axis.
    pub const MAX_POSITION: u32 = 63;
    /// Largest valid width or height.
    pub const MAX_SIZE: u32 = 64;
    /// Largest valid per-corner AO value (unoccluded).
    pub const MAX_AO: u8 = 3;

    // The bit layout (the tables above) as named shifts and masks, for code that writes quads
    // word by word (a mesher's inner loops) instead of through `encode`. Being constants, they
    // fold into the same immediates a hand-written shift would use.

    /// Bit offset in `position_size` of the x position, [`FIELD_MASK`](Self::FIELD_MASK) wide.
    pub const X_SHIFT: u32 = 0;
    /// Bit offset in `position_size` of the y position, [`FIELD_MASK`](Self::FIELD_MASK) wide.
    pub const Y_SHIFT: u32 = 6;
    /// Bit offset in `position_size` of the z position, [`FIELD_MASK`](Self::FIELD_MASK) wide.
    pub const Z_SHIFT: u32 = 12;
    /// The position shifts by axis (x, y, z): [`X_SHIFT`](Self::X_SHIFT),
    /// [`Y_SHIFT`](Self::Y_SHIFT), [`Z_SHIFT`](Self::Z_SHIFT).
    pub const POSITION_SHIFTS: [u32; 3] = [Self::X_SHIFT, Self::Y_SHIFT, Self::Z_SHIFT];
    /// Bit offset in `position_size` of `width - 1`, [`FIELD_MASK`](Self::FIELD_MASK) wide.
    pub const WIDTH_SHIFT: u32 = 18;
    /// Bit offset in `position_size` of `height - 1`, [`FIELD_MASK`](Self::FIELD_MASK) wide.
    pub const HEIGHT_SHIFT: u32 = 24;
    /// Width in bits of each `position_size` field (a position axis, `width - 1`,
    /// `height - 1`).
    pub const FIELD_BITS: u32 = 6;
    /// Mask of a `position_size` field once shifted down: `(1 << FIELD_BITS) - 1`.
    pub const FIELD_MASK: u32 = (1 << Self::FIELD_BITS) - 1;
    /// Bit offset in `face_ao_block` of the face direction's index,
    /// [`FACE_MASK`](Self::FACE_MASK) wide.
    pub const FACE_SHIFT: u32 = 0;
    /// Mask of the face direction's index once shifted down (3 bits).
    pub const FACE_MASK: u32 = 7;
    /// Bit offset in `face_ao_block` of the 4 packed AO values (corner `i` at bits
    /// `AO_SHIFT + 2i..AO_SHIFT + 2i + 2`), [`AO_MASK`](Self::AO_MASK) wide.
    pub const AO_SHIFT: u32 = 3;
    /// Mask of the 4 packed AO values once shifted down (8 bits).
    pub const AO_MASK: u32 = 0xFF;
    /// The 4 packed AO values of a quad with every corner unoccluded ([`MAX_AO`](Self::MAX_AO)).
    pub const AO_UNOCCLUDED: u32 = 0xFF;
    /// Bit offset in `face_ao_block` of the block id, [`BLOCK_MASK`](Self::BLOCK_MASK) wide.
    pub const BLOCK_SHIFT: u32 = 11;
    /// Mask of the block id once shifted down (16 bits).
    pub const BLOCK_MASK: u32 = 0xFFFF;
    /// Bits of one corner's AO value inside the AO field (corner `i` at `2i..2i + 2`).
    pub const AO_CORNER_BITS: u32 = 2;
    /// Bit offset of `face_ao_block` in [`to_u64`](Self::to_u64)'s value.
    pub const WORD1_SHIFT: u32 = 32;

    /// Both words as one `u64`, `position_size` in the low half: the quad's 8 bytes as a
    /// little-endian integer. Lets a mesher add to both words with one 64-bit add.
    #[inline(always)]
    pub const fn to_u64(self) -> u64 {
        (self.face_ao_block as u64) << Self::WORD1_SHIFT | self.position_size as u64
    }

    /// The AO field (shifted down) of the 4 corner values `ao` (each at most
    /// [`MAX_AO`](Self::MAX_AO); larger values spill into the next corner).
    #[inline(always)]
    pub const fn pack_ao(ao: [u8; 4]) -> u32 {
        let mut packed = 0;
        let mut i = 0;
        while i < 4 {
            packed |= (ao[i] as u32) << (Self::AO_CORNER_BITS * i as u32);
            i += 1;
        }
        packed
    }

    /// The 4 corner values of an AO field (shifted down; bits past the field are ignored).
    #[inline(always)]
    pub const fn unpack_ao(field: u32) -> [u8; 4] {
        let mut ao = [0u8; 4];
        let mut i = 0;
        while i < 4 {
            ao[i] = ((field >> (Self::AO_CORNER_BITS * i as u32)) & Self::MAX_AO as u32) as u8;
            i += 1;
        }
        ao
    }

    /// The quad whose [`to_u64`](Self::to_u64) is `both`.
    #[inline(always)]
    pub const fn from_u64(both: u64) -> PackedQuad {
        PackedQuad {
            position_size: both as u32,
            face_ao_block: (both >> Self::WORD1_SHIFT) as u32,
        }
    }

    /// The WGSL struct `PackedQuad { position_size: u32, face_ao_block: u32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "PackedQuad",
        size: size_of::<PackedQuad>(),
        members: &[
            member(
                "position_size",
                offset_of!(PackedQuad, position_size),
                WgslType::U32,
            ),
            member(
                "face_ao_block",
                offset_of!(PackedQuad, face_ao_block),
                WgslType::U32,
            ),
        ],
    };

    /// Packs `fields`, rejecting a position axis above 63, a width or height outside `1..=64`
    /// and an AO value above 3 with [`FormatError::IntegerOutOfRange`] naming the field.
    pub fn encode(fields: &PackedQuadFields) -> Result<PackedQuad, FormatError> {
        let [x, y, z] = fields.position;
        let x = check_max("PackedQuad.position.x", x, Self::MAX_POSITION)?;
        let y = check_max("PackedQuad.position.y", y, Self::MAX_POSITION)?;
        let z = check_max("PackedQuad.position.z", z, Self::MAX_POSITION)?;
        let w = check_range("PackedQuad.width", fields.width, 1, Self::MAX_SIZE)? - 1;
        let h = check_range("PackedQuad.height", fields.height, 1, Self::MAX_SIZE)? - 1;
        const AO: [&str; 4] = [
            "PackedQuad.ao[0]",
            "PackedQuad.ao[1]",
            "PackedQuad.ao[2]",
            "PackedQuad.ao[3]",
        ];
        for (&value, field) in fields.ao.iter().zip(AO) {
            check_max(field, value.into(), Self::MAX_AO.into())?;
        }
        let ao = Self::pack_ao(fields.ao);
        Ok(PackedQuad {
            position_size: x << Self::X_SHIFT
                | y << Self::Y_SHIFT
                | z << Self::Z_SHIFT
                | w << Self::WIDTH_SHIFT
                | h << Self::HEIGHT_SHIFT,
            face_ao_block: u32::from(fields.face.index()) << Self::FACE_SHIFT
                | ao << Self::AO_SHIFT
                | u32::from(fields.block.0) << Self::BLOCK_SHIFT,
        })
    }

    /// The block type the quad shows (word 1, bits 11..27), without decoding the rest.
    pub fn block(self) -> BlockId {
        BlockId(((self.face_ao_block >> Self::BLOCK_SHIFT) & Self::BLOCK_MASK) as u16)
    }

    /// Unpacks the fields, or fails with [`FormatError::InvalidFaceDirection`] for face 6 or 7
    /// and [`FormatError::ReservedBitsSet`] if a reserved bit is set.
    pub fn decode(self) -> Result<PackedQuadFields, FormatError> {
        let w0 = self.position_size;
        let w1 = self.face_ao_block;
        check_reserved("PackedQuad.position_size", w0, WORD0_RESERVED)?;
        check_reserved("PackedQuad.face_ao_block", w1, WORD1_RESERVED)?;
        let field = |shift: u32| (w0 >> shift) & Self::FIELD_MASK;
        Ok(PackedQuadFields {
            position: Self::POSITION_SHIFTS.map(field),
            width: field(Self::WIDTH_SHIFT) + 1,
            height: field(Self::HEIGHT_SHIFT) + 1,
            face: FaceDirection::from_index(((w1 >> Self::FACE_SHIFT) & Self::FACE_MASK) as u8)?,
            ao: Self::unpack_ao(w1 >> Self::AO_SHIFT),
            block: self.block(),
        })
    }
}

impl PackedQuadFields {
    /// The quad's 4 corners in chunk-local voxel units, counter-clockwise seen from outside
    /// (front-facing for the outward normal with `FrontFace::Ccw`): draw them as the triangles
    /// `(0, 1, 2)` and `(0, 2, 3)`.
    ///
    /// The face lies in the plane of the voxel's face: for positive directions that is
    /// `position + 1` along the normal, for negative ones `position` itself. Corner 0 is the
    /// quad's minimum corner; the others step by `width` along the width axis (`du = 1`) and by
    /// `height` along the height axis (`dv = 1`) in this order:
    ///
    /// | face               | corner 0 | corner 1 | corner 2 | corner 3 |
    /// | ------------------ | -------- | -------- | -------- | -------- |
    /// | `NegX`, `NegY`, `PosZ` | (0, 0) | (1, 0)   | (1, 1)   | (0, 1)   |
    /// | `PosX`, `PosY`, `NegZ` | (0, 0) | (0, 1)   | (1, 1)   | (1, 0)   |
    ///
    /// (`(du, dv)`; the second row is the first with `du` and `dv` swapped, because for those
    /// faces width axis x height axis points against the normal.)
    ///
    /// Coordinates are at most `63 + 64 = 127`, so they never overflow.
    pub fn corners(&self) -> [[u32; 3]; 4] {
        let face = self.face;
        let mut base = self.position;
        if face.is_positive() {
            base[face.normal_axis()] += 1;
        }
        let swap = matches!(
            face,
            FaceDirection::PosX | FaceDirection::PosY | FaceDirection::NegZ
        );
        let steps: [(u32, u32); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
        steps.map(|(a, b)| {
            let (du, dv) = if swap { (b, a) } else { (a, b) };
            let mut corner = base;
            corner[face.width_axis()] += du * self.width;
            corner[face.height_axis()] += dv * self.height;
            corner
        })
    }
}
