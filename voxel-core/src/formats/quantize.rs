//! Unsigned normalized (unorm) quantization of positions and texture coordinates.
//!
//! A value `v` in `0.0..=extent` is stored as the integer `code = round(v / extent * MAX)`
//! (`MAX` = 65535 for 16 bits, 255 for 8 bits; ties round up) and read back as
//! `decode(code) = (code * (1 / MAX)) * extent`, two `f32` multiplications that a GPU performs
//! bit for bit the same way (WGSL `unorm16_decode` / `unorm8_decode`). Code 0 decodes to
//! exactly 0 and code `MAX` to exactly `extent`.
//!
//! **Bound** ([`UnormExtent::max_error`]): for every valid `v`,
//! `|unorm16_decode(unorm16_encode(v, e), e) - v| <= e * (0.5 / 65535 + 2 * f32::EPSILON)`:
//! half a quantization step, plus the rounding of the two `f32` multiplications in the decode
//! (the encode runs in `f64` and rounds exactly). For a padded 64-voxel chunk that is
//! 0.0005 voxels. Likewise for 8 bits with 255 in place of 65535.
//!
//! Encoding rejects NaN, infinite, negative and larger-than-extent values with
//! [`FormatError::QuantizeOutOfRange`], which names the value and the extent.

use glam::{Vec2, Vec3};

use super::FormatError;
use crate::ChunkSize;

/// Largest unorm16 code.
pub const UNORM16_MAX: u16 = u16::MAX;

/// Largest unorm8 code.
pub const UNORM8_MAX: u8 = u8::MAX;

/// The value of one unorm16 step at extent 1: `1 / 65535`, rounded to `f32`.
pub const UNORM16_STEP: f32 = 1.0 / 65535.0;

/// The value of one unorm8 step: `1 / 255`, rounded to `f32`.
pub const UNORM8_STEP: f32 = 1.0 / 255.0;

/// The length that the largest unorm code stands for: a finite, normal (not subnormal), positive
/// `f32`. (Subnormal extents are rejected because their decoded values would round to a grid
/// coarser than the stated bound.)
///
/// Positions of [`BlockVertex`](super::BlockVertex) and [`ClutterUnit`](super::ClutterUnit)
/// are chunk-local and quantized over `0..=extent`; the natural extent is the padded chunk edge
/// ([`UnormExtent::padded_chunk`]), which also covers vertices on the apron. Texture
/// coordinates use [`UnormExtent::UNIT`].
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct UnormExtent(f32);

impl UnormExtent {
    /// Extent 1, for texture coordinates in `0..=1`.
    pub const UNIT: UnormExtent = UnormExtent(1.0);

    /// The extent, or [`FormatError::InvalidFloat`] (field `"extent"`) unless it is finite,
    /// normal and greater than zero (at least `f32::MIN_POSITIVE`).
    pub fn new(extent: f32) -> Result<UnormExtent, FormatError> {
        if extent.is_normal() && extent > 0.0 {
            Ok(UnormExtent(extent))
        } else {
            Err(FormatError::InvalidFloat {
                field: "extent",
                value: extent,
                expected: "finite, normal and > 0",
            })
        }
    }

    /// The padded chunk edge, `size.edge() + 2` voxels: room for a one-voxel apron on each
    /// side once positions are shifted by +1.
    pub const fn padded_chunk(size: ChunkSize) -> UnormExtent {
        UnormExtent(size.padded_edge() as f32)
    }

    /// An extent for positions in padded voxel coordinates up to `padded_edge - 1/2` (the
    /// vertices of NoCubes) on which every **integer** position has an exact code: the extent
    /// is `65535 / 2^k` for the largest `k` with `(padded_edge - 1/2) * 2^k <= 65535`, so
    /// integer `x` encodes to `x * 2^k` and decodes to `x` within a few `f32` rounding steps
    /// (2^k = 1024 for a 62^3 chunk, 4096 for 8^3). A mesh whose lattice points must meet
    /// integer-positioned geometry (the corners of `PackedQuad`s) uses it instead of
    /// [`padded_chunk`](Self::padded_chunk), whose integer positions round to the nearest of
    /// `65535 / padded_edge` steps per voxel.
    pub const fn padded_lattice(size: ChunkSize) -> UnormExtent {
        // Twice the largest position, in half voxels, so the bound stays an integer.
        let half_voxels = 2 * size.padded_edge() as u32 - 1;
        let mut scale = 1u32 << 15;
        while half_voxels * scale > 2 * 65535 {
            scale >>= 1;
        }
        UnormExtent(65535.0 / scale as f32)
    }

    /// The extent as a number.
    #[inline]
    pub const fn get(self) -> f32 {
        self.0
    }

    /// The stated unorm16 bound for this extent: `extent * (0.5 / 65535 + 2 * f32::EPSILON)`.
    pub fn max_error(self) -> f32 {
        unorm_max_error(self.0, 65535.0)
    }

    /// The stated unorm8 bound for this extent: `extent * (0.5 / 255 + 2 * f32::EPSILON)`.
    pub fn max_error_unorm8(self) -> f32 {
        unorm_max_error(self.0, 255.0)
    }
}

fn unorm_max_error(extent: f32, max_code: f64) -> f32 {
    (f64::from(extent) * (0.5 / max_code + 2.0 * f64::from(f32::EPSILON))) as f32
}

/// Quantizes `value` in `0.0..=extent` to 16 bits, rounding to nearest.
///
/// Fails with [`FormatError::QuantizeOutOfRange`] (field `"unorm16"`) for NaN, infinite,
/// negative or larger-than-extent input.
pub fn unorm16_encode(value: f32, extent: UnormExtent) -> Result<u16, FormatError> {
    unorm_encode(value, extent, 65535.0, "unorm16").map(|c| c as u16)
}

/// The value a unorm16 code stands for: `(code * UNORM16_STEP) * extent`.
#[inline]
pub fn unorm16_decode(code: u16, extent: UnormExtent) -> f32 {
    (f32::from(code) * UNORM16_STEP) * extent.0
}

/// Quantizes `value` in `0.0..=1.0` to 8 bits, rounding to nearest.
///
/// Fails with [`FormatError::QuantizeOutOfRange`] (field `"unorm8"`) for NaN, infinite,
/// negative or larger-than-1 input.
pub fn unorm8_encode(value: f32) -> Result<u8, FormatError> {
    unorm8_encode_field(value, "unorm8")
}

/// The value a unorm8 code stands for: `code * UNORM8_STEP`, in `0.0..=1.0`.
#[inline]
pub fn unorm8_decode(code: u8) -> f32 {
    f32::from(code) * UNORM8_STEP
}

/// Quantizes each axis of a position in `0.0..=extent` to 16 bits.
///
/// Fails with [`FormatError::QuantizeOutOfRange`] (field `"unorm16"`) naming the first
/// rejected axis value.
pub fn unorm16x3_encode(position: Vec3, extent: UnormExtent) -> Result<[u16; 3], FormatError> {
    unorm16x3_encode_field(position, extent, "unorm16")
}

/// The position three unorm16 codes stand for.
#[inline]
pub fn unorm16x3_decode(codes: [u16; 3], extent: UnormExtent) -> Vec3 {
    Vec3::from_array(codes.map(|c| unorm16_decode(c, extent)))
}

/// Quantizes texture coordinates in `0.0..=1.0` to 16 bits each.
pub fn unorm16x2_encode(uv: Vec2) -> Result<[u16; 2], FormatError> {
    unorm16x2_encode_field(uv, "unorm16")
}

/// The texture coordinates two unorm16 codes (extent 1) stand for.
#[inline]
pub fn unorm16x2_decode(codes: [u16; 2]) -> Vec2 {
    Vec2::from_array(codes.map(|c| unorm16_decode(c, UnormExtent::UNIT)))
}

pub(crate) fn unorm16x3_encode_field(
    position: Vec3,
    extent: UnormExtent,
    field: &'static str,
) -> Result<[u16; 3], FormatError> {
    let axis = |v: f32| unorm_encode(v, extent, 65535.0, field).map(|c| c as u16);
    Ok([axis(position.x)?, axis(position.y)?, axis(position.z)?])
}

pub(crate) fn unorm16x2_encode_field(
    uv: Vec2,
    field: &'static str,
) -> Result<[u16; 2], FormatError> {
    let axis = |v: f32| unorm_encode(v, UnormExtent::UNIT, 65535.0, field).map(|c| c as u16);
    Ok([axis(uv.x)?, axis(uv.y)?])
}

pub(crate) fn unorm8_encode_field(value: f32, field: &'static str) -> Result<u8, FormatError> {
    unorm_encode(value, UnormExtent::UNIT, 255.0, field).map(|c| c as u8)
}

/// `round(value / extent * max_code)` in `f64`, ties up; the range check rejects NaN too.
fn unorm_encode(
    value: f32,
    extent: UnormExtent,
    max_code: f64,
    field: &'static str,
) -> Result<u32, FormatError> {
    if !(0.0..=extent.0).contains(&value) {
        return Err(FormatError::QuantizeOutOfRange {
            field,
            value,
            extent: extent.0,
        });
    }
    let scaled = f64::from(value) / f64::from(extent.0) * max_code;
    // `scaled` is in 0..=max_code, so truncation is floor and the result fits.
    Ok((scaled + 0.5) as u32)
}
