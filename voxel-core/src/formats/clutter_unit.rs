//! `ClutterUnit`: one clutter instance (grass blade, pebble, flower) in 20 bytes.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use super::FormatError;
use super::error::check_max;
use super::octahedral::{oct16_decode, oct16_encode_field};
use super::quantize::{
    UnormExtent, unorm8_decode, unorm8_encode_field, unorm16x2_decode, unorm16x2_encode_field,
    unorm16x3_decode, unorm16x3_encode_field,
};
use super::wgsl::{WgslStruct, WgslType, member};

/// One clutter instance, drawn as a small textured card or mesh on a surface (Project
/// Ascendant's ClutterUnit).
///
/// ```text
/// byte 0        2        4        6        8        10       12       14   15   16                20
///      +--------+--------+--------+--------+--------+--------+--------+----+----+-----------------+
///      |  pos x |  pos y |  pos z | normal |settings|  uv u  |  uv v  | sw | sh |  tint (RGBA8)   |
///      +--------+--------+--------+--------+--------+--------+--------+----+----+-----------------+
/// ```
///
/// | bytes  | field      | encoding                                                          |
/// | ------ | ---------- | ----------------------------------------------------------------- |
/// | 0..6   | `position` | 3 x unorm16 over `0..=extent`, chunk-local (like [`BlockVertex`]) |
/// | 6..8   | `normal`   | octahedral 8+8 surface normal, the clutter's up direction         |
/// | 8..10  | `settings` | bits 0..8 kind, bits 8..12 scale step, bits 12..16 random seed    |
/// | 10..14 | `uv`       | 2 x unorm16 over `0..=1`: the sprite's corner in the atlas        |
/// | 14..16 | `uv_size`  | 2 x unorm8 over `0..=1`: the sprite's width, height in the atlas  |
/// | 16..20 | `tint`     | RGBA8, red in the lowest byte; multiplies the sprite's colour     |
///
/// The `settings` word, low bits first:
///
/// | bits   | field        | range  | meaning                                                 |
/// | ------ | ------------ | ------ | ------------------------------------------------------- |
/// | 0..8   | `kind`       | 0..256 | which clutter (an index into the backend's clutter set) |
/// | 8..12  | `scale_step` | 0..16  | size class: an index into the backend's scale table     |
/// | 12..16 | `seed`       | 0..16  | random bits for per-instance variation (rotation, sway) |
///
/// Every bit pattern decodes. WGSL reads the 20 bytes as 5 `u32` words; `u16` / `u8` fields
/// pack little-endian (`settings_uv_u = settings | uv_u << 16`,
/// `uv_v_size = uv_v | size_w << 16 | size_h << 24`).
///
/// [`BlockVertex`]: super::BlockVertex
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct ClutterUnit {
    /// Unorm16 position codes, x, y, z.
    pub position: [u16; 3],
    /// Octahedral 8+8 normal code.
    pub normal: u16,
    /// Kind, scale step and seed (layout above).
    pub settings: u16,
    /// Unorm16 atlas position codes, u, v.
    pub uv: [u16; 2],
    /// Unorm8 atlas size codes, width, height.
    pub uv_size: [u8; 2],
    /// RGBA8 tint, red in the lowest byte.
    pub tint: u32,
}

const _: () = assert!(
    size_of::<ClutterUnit>() == 20,
    "ClutterUnit must be 20 bytes"
);
const _: () = assert!(
    offset_of!(ClutterUnit, tint) == 16,
    "tint must be 4-aligned at 16"
);

/// The unpacked fields of a [`ClutterUnit`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClutterUnitFields {
    /// Chunk-local position, each axis in `0.0..=extent`.
    pub position: Vec3,
    /// Surface normal: any finite non-zero vector (length is ignored); decodes to unit length.
    pub normal: Vec3,
    /// Which clutter, `0..=255`.
    pub kind: u8,
    /// Size class, `0..=15`.
    pub scale_step: u8,
    /// Random variation bits, `0..=15`.
    pub seed: u8,
    /// The sprite's corner in the atlas, each in `0.0..=1.0`.
    pub uv: Vec2,
    /// The sprite's size in the atlas, each in `0.0..=1.0` (quantized to 8 bits).
    pub uv_size: Vec2,
    /// RGBA tint.
    pub tint: [u8; 4],
}

impl ClutterUnit {
    /// Largest valid scale step.
    pub const MAX_SCALE_STEP: u8 = 15;
    /// Largest valid seed.
    pub const MAX_SEED: u8 = 15;

    /// The WGSL struct
    /// `ClutterUnit { position_xy, position_z_normal, settings_uv_u, uv_v_size, tint: u32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "ClutterUnit",
        size: size_of::<ClutterUnit>(),
        members: &[
            member(
                "position_xy",
                offset_of!(ClutterUnit, position),
                WgslType::U32,
            ),
            member(
                "position_z_normal",
                offset_of!(ClutterUnit, position) + 2 * size_of::<u16>(),
                WgslType::U32,
            ),
            member(
                "settings_uv_u",
                offset_of!(ClutterUnit, settings),
                WgslType::U32,
            ),
            member(
                "uv_v_size",
                offset_of!(ClutterUnit, uv) + size_of::<u16>(),
                WgslType::U32,
            ),
            member("tint", offset_of!(ClutterUnit, tint), WgslType::U32),
        ],
    };

    /// Quantizes `fields` with the position `extent`.
    ///
    /// Fails with [`FormatError::QuantizeOutOfRange`] for a position, uv or uv size out of its
    /// range, [`FormatError::InvalidNormal`] for a NaN, infinite or zero normal, and
    /// [`FormatError::IntegerOutOfRange`] for a scale step or seed above 15; each names the
    /// field (`"ClutterUnit.position"`, `"ClutterUnit.scale_step"`, ...).
    pub fn encode(
        fields: &ClutterUnitFields,
        extent: UnormExtent,
    ) -> Result<ClutterUnit, FormatError> {
        let scale = check_max(
            "ClutterUnit.scale_step",
            fields.scale_step.into(),
            Self::MAX_SCALE_STEP.into(),
        )?;
        let seed = check_max(
            "ClutterUnit.seed",
            fields.seed.into(),
            Self::MAX_SEED.into(),
        )?;
        let size_w = unorm8_encode_field(fields.uv_size.x, "ClutterUnit.uv_size")?;
        let size_h = unorm8_encode_field(fields.uv_size.y, "ClutterUnit.uv_size")?;
        Ok(ClutterUnit {
            position: unorm16x3_encode_field(fields.position, extent, "ClutterUnit.position")?,
            normal: oct16_encode_field(fields.normal, "ClutterUnit.normal")?,
            settings: (u32::from(fields.kind) | scale << 8 | seed << 12) as u16,
            uv: unorm16x2_encode_field(fields.uv, "ClutterUnit.uv")?,
            uv_size: [size_w, size_h],
            tint: u32::from_le_bytes(fields.tint),
        })
    }

    /// Unpacks the fields with the position `extent`. Every bit pattern is valid; the normal is
    /// always unit length.
    pub fn decode(self, extent: UnormExtent) -> ClutterUnitFields {
        ClutterUnitFields {
            position: unorm16x3_decode(self.position, extent),
            normal: oct16_decode(self.normal),
            kind: self.settings as u8,
            scale_step: ((self.settings >> 8) & 0xF) as u8,
            seed: (self.settings >> 12) as u8,
            uv: unorm16x2_decode(self.uv),
            uv_size: Vec2::new(
                unorm8_decode(self.uv_size[0]),
                unorm8_decode(self.uv_size[1]),
            ),
            tint: self.tint.to_le_bytes(),
        }
    }
}
