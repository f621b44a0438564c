//! The one error type shared by every packed format.

use core::fmt;

/// Why a value could not be encoded into, or decoded from, a packed format.
///
/// Every variant names the field (as `"Format.field"`, e.g. `"PackedQuad.width"`) and the
/// rejected value, so a message read in a log points at the exact input. Encoders never mask or
/// clamp silently: a value that does not fit is one of these errors.
///
/// Derives only `PartialEq` (not `Eq`) because some variants carry the rejected `f32`; compare
/// variants with `matches!` when the value may be NaN.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum FormatError {
    /// An integer field is outside `min..=max` (too large for its bits, or below its minimum).
    IntegerOutOfRange {
        /// The field, as `"Format.field"`.
        field: &'static str,
        /// The rejected value.
        value: i64,
        /// Smallest valid value.
        min: i64,
        /// Largest valid value.
        max: i64,
    },
    /// A float field is NaN, infinite, or outside the range its documentation states.
    InvalidFloat {
        /// The field, as `"Format.field"`.
        field: &'static str,
        /// The rejected value.
        value: f32,
        /// What the field requires, e.g. `"finite and >= 0"`.
        expected: &'static str,
    },
    /// A value to quantize is NaN, infinite, negative or larger than the quantization extent.
    QuantizeOutOfRange {
        /// The field, as `"Format.field"` (or `"unorm16"` / `"unorm8"` from the bare helpers).
        field: &'static str,
        /// The rejected value.
        value: f32,
        /// The extent: valid values are `0.0..=extent`.
        extent: f32,
    },
    /// A vector to encode as an octahedral normal is zero-length or has a NaN or infinite
    /// component.
    InvalidNormal {
        /// The field, as `"Format.field"` (or `"oct16"` / `"oct32"` from the bare helpers).
        field: &'static str,
        /// The rejected vector.
        value: [f32; 3],
    },
    /// A face direction index is not in `0..6`.
    InvalidFaceDirection {
        /// The rejected index.
        value: u8,
    },
    /// A chunk kind is not one of the [`ChunkKind`](super::ChunkKind) values.
    InvalidChunkKind {
        /// The rejected value.
        value: u32,
    },
    /// Bits that the layout reserves (and requires to be zero) are set.
    ReservedBitsSet {
        /// The packed word, as `"Format.word"`.
        field: &'static str,
        /// The offending bits, already masked to the reserved range.
        bits: u32,
    },
    /// A buffer range whose end (`offset + count`) does not fit in `u32`.
    RangeOverflow {
        /// The range, as `"Format.field"`.
        field: &'static str,
        /// The range's first element.
        offset: u32,
        /// The range's total element count.
        count: u64,
    },
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            FormatError::IntegerOutOfRange {
                field,
                value,
                min,
                max,
            } => write!(f, "{field} = {value} is outside {min}..={max}"),
            FormatError::InvalidFloat {
                field,
                value,
                expected,
            } => write!(f, "{field} = {value} must be {expected}"),
            FormatError::QuantizeOutOfRange {
                field,
                value,
                extent,
            } => write!(
                f,
                "{field} = {value} cannot be quantized: it must be finite and in 0..={extent}"
            ),
            FormatError::InvalidNormal { field, value } => write!(
                f,
                "{field} = {value:?} is not a valid normal: it must be finite and non-zero"
            ),
            FormatError::InvalidFaceDirection { value } => {
                write!(f, "face direction {value} is not in 0..6")
            }
            FormatError::InvalidChunkKind { value } => {
                write!(
                    f,
                    "chunk kind {value} is not Empty (0), Mesh (1) or Sprite (2)"
                )
            }
            FormatError::ReservedBitsSet { field, bits } => {
                write!(f, "{field} has reserved bits set: {bits:#010x}")
            }
            FormatError::RangeOverflow {
                field,
                offset,
                count,
            } => write!(
                f,
                "{field}: offset {offset} + count {count} does not fit in u32"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for FormatError {}

/// `Ok(value)` if `value <= max`, else [`FormatError::IntegerOutOfRange`] naming `field`.
pub(crate) fn check_max(field: &'static str, value: u32, max: u32) -> Result<u32, FormatError> {
    check_range(field, value, 0, max)
}

/// `Ok(value)` if `min <= value <= max`, else [`FormatError::IntegerOutOfRange`] naming `field`.
pub(crate) fn check_range(
    field: &'static str,
    value: u32,
    min: u32,
    max: u32,
) -> Result<u32, FormatError> {
    if (min..=max).contains(&value) {
        Ok(value)
    } else {
        Err(FormatError::IntegerOutOfRange {
            field,
            value: value.into(),
            min: min.into(),
            max: max.into(),
        })
    }
}

/// `Ok(())` if `word & reserved_mask == 0`, else [`FormatError::ReservedBitsSet`].
pub(crate) fn check_reserved(
    field: &'static str,
    word: u32,
    reserved_mask: u32,
) -> Result<(), FormatError> {
    match word & reserved_mask {
        0 => Ok(()),
        bits => Err(FormatError::ReservedBitsSet { field, bits }),
    }
}
