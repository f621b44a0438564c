//! The versioned binary form of one [`PaletteChunk`].
//!
//! # Layout (version 1)
//!
//! All multi-byte fields are little-endian.
//!
//! | offset | size | field | valid values |
//! | --- | --- | --- | --- |
//! | 0 | 4 | magic | `b"VXCH"` |
//! | 4 | 1 | version | `1` |
//! | 5 | 1 | chunk edge | `8`, `16`, `32`, `62` |
//! | 6 | 1 | bits per voxel | `0` (uniform), `1`, `2`, `4`, `8` (palette indices), `16` (raw ids) |
//! | 7 | 1 | reserved | `0` |
//! | 8 | 2 | palette length `n` (u16) | exactly 1 when uniform; `1..=2^bits` for 1..8 bits; 0 for 16 bits |
//! | 10 | `2n` | palette entries (u16 block ids) | distinct |
//! | `10 + 2n` | `ceil(volume * bits / 8)` | voxels | see below |
//!
//! Voxel `i` (linear order, x fastest: `x + e * (y + e * z)`) occupies bits
//! `i * bits .. (i + 1) * bits` of the voxel bytes, counting from bit 0 of byte 0 (little-endian
//! bit order). With 1..8 bits it is an index `< n` into the palette; with 16 bits it is the block
//! id itself. Bits past `volume * bits` in the last byte must be zero (every supported volume is
//! a multiple of 8, so there are none today). A uniform chunk is the header plus its one palette
//! entry: 12 bytes.
//!
//! The encoder writes the chunk's current width and palette as they are (including free palette
//! entries); [`PaletteChunk::compact`] first gives the smallest encoding. The decoder accepts any
//! valid width, rejects every malformation with a named [`CodecError`], and allocates only after
//! checking that the input holds exactly the bytes the header declares (at most
//! `10 + 512 + 62^3 * 2` bytes).
//!
//! ```
//! use voxel_core::{BlockId, ChunkSize, LocalPos};
//! use voxel_core::storage::{decode_chunk, encode_chunk, CodecError, PaletteChunk, VoxelStorage};
//!
//! let mut chunk = PaletteChunk::new(ChunkSize::S8);
//! chunk.set(LocalPos::new(1, 2, 3, ChunkSize::S8)?, BlockId(42))?;
//! let mut bytes = Vec::new();
//! encode_chunk(&chunk, &mut bytes);
//! assert_eq!(bytes.len(), 10 + 2 * 2 + 512 / 8);
//! assert_eq!(decode_chunk(&bytes), Ok(chunk));
//! assert_eq!(decode_chunk(&bytes[..20]), Err(CodecError::Truncated { needed: 78, got: 20 }));
//! # Ok::<(), voxel_core::CoordError>(())
//! ```

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

use crate::{BlockId, ChunkSize};

use super::PaletteChunk;
use super::packed_bits::{PackedBits, low_bits};
use super::palette::Repr;

/// The first four bytes of every encoded chunk.
pub const MAGIC: [u8; 4] = *b"VXCH";
/// The format version this crate writes and reads.
pub const CODEC_VERSION: u8 = 1;
/// Bytes before the palette entries.
pub const HEADER_LEN: usize = 10;

/// A byte string that is not a valid encoded chunk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum CodecError {
    /// The input does not start with `b"VXCH"` (checked on as many bytes as there are).
    BadMagic,
    /// A version other than [`CODEC_VERSION`].
    UnsupportedVersion(u8),
    /// A chunk edge other than 8, 16, 32, 62.
    BadChunkEdge(u8),
    /// A width other than 0, 1, 2, 4, 8, 16.
    BadBitsPerVoxel(u8),
    /// The reserved byte is not zero.
    NonZeroReserved,
    /// More palette entries than the width allows (more than 1 when uniform, more than
    /// `2^bits` for indices, any in 16-bit raw mode).
    PaletteTooLarge {
        /// The declared palette length.
        len: u16,
        /// The declared bits per voxel.
        bits: u8,
    },
    /// A uniform or indexed chunk with no palette entry.
    EmptyPalette,
    /// A block id listed twice in the palette.
    DuplicatePaletteEntry(BlockId),
    /// A voxel's palette index is not below the palette length.
    PaletteIndexOutOfRange {
        /// The index found.
        index: u32,
        /// The palette length.
        len: u16,
        /// The voxel's linear index.
        voxel: usize,
    },
    /// Fewer bytes than the header declares.
    Truncated {
        /// Bytes required.
        needed: usize,
        /// Bytes given.
        got: usize,
    },
    /// More bytes than the header declares.
    TrailingBytes {
        /// Bytes past the end of the chunk.
        extra: usize,
    },
    /// Bits after the last voxel in the final byte are not zero.
    NonZeroPadding,
}

impl fmt::Display for CodecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            CodecError::BadMagic => write!(f, "not an encoded chunk: magic is not \"VXCH\""),
            CodecError::UnsupportedVersion(v) => {
                write!(f, "unsupported chunk format version {v} (supported: 1)")
            }
            CodecError::BadChunkEdge(e) => {
                write!(f, "chunk edge {e} is not one of 8, 16, 32, 62")
            }
            CodecError::BadBitsPerVoxel(b) => {
                write!(f, "{b} bits per voxel is not one of 0, 1, 2, 4, 8, 16")
            }
            CodecError::NonZeroReserved => write!(f, "the reserved header byte is not zero"),
            CodecError::PaletteTooLarge { len, bits } => {
                write!(
                    f,
                    "palette of {len} entries is too large for {bits} bits per voxel"
                )
            }
            CodecError::EmptyPalette => write!(f, "the palette is empty"),
            CodecError::DuplicatePaletteEntry(id) => {
                write!(f, "block id {} appears twice in the palette", id.0)
            }
            CodecError::PaletteIndexOutOfRange { index, len, voxel } => write!(
                f,
                "voxel {voxel} has palette index {index}, palette has {len} entries"
            ),
            CodecError::Truncated { needed, got } => {
                write!(f, "chunk truncated: {needed} bytes needed, {got} given")
            }
            CodecError::TrailingBytes { extra } => {
                write!(f, "{extra} bytes after the end of the chunk")
            }
            CodecError::NonZeroPadding => {
                write!(f, "padding bits after the last voxel are not zero")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for CodecError {}

/// Bytes holding `volume` voxels of `bits` bits.
const fn voxel_bytes(volume: usize, bits: usize) -> usize {
    (volume * bits).div_ceil(8)
}

/// The exact length [`encode_chunk`] writes for `chunk`.
pub fn encoded_len(chunk: &PaletteChunk) -> usize {
    HEADER_LEN
        + 2 * chunk.palette().len()
        + voxel_bytes(chunk.size.volume(), chunk.bits_per_voxel().into())
}

/// Appends the encoding of `chunk` to `out` (see the [module docs](self) for the layout).
pub fn encode_chunk(chunk: &PaletteChunk, out: &mut Vec<u8>) {
    out.reserve(encoded_len(chunk));
    let bits = chunk.bits_per_voxel();
    let palette = chunk.palette();
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&[CODEC_VERSION, chunk.size.edge() as u8, bits, 0]);
    out.extend_from_slice(&(palette.len() as u16).to_le_bytes());
    for id in palette {
        out.extend_from_slice(&id.0.to_le_bytes());
    }
    let words = match &chunk.repr {
        Repr::Uniform(_) => return,
        Repr::Indexed(ix) => ix.indices.words(),
        Repr::Raw(raw) => raw.values.words(),
    };
    let mut left = voxel_bytes(chunk.size.volume(), bits.into());
    for word in words {
        let bytes = word.to_le_bytes();
        let n = left.min(8);
        out.extend_from_slice(&bytes[..n]);
        left -= n;
    }
}

/// The chunk encoded in `bytes`, which must hold exactly one encoded chunk.
pub fn decode_chunk(bytes: &[u8]) -> Result<PaletteChunk, CodecError> {
    let got = bytes.len();
    let magic_seen = got.min(MAGIC.len());
    if bytes[..magic_seen] != MAGIC[..magic_seen] {
        return Err(CodecError::BadMagic);
    }
    let Some(&[version, edge, bits, reserved, len_lo, len_hi]) = bytes.get(4..HEADER_LEN) else {
        return Err(CodecError::Truncated {
            needed: HEADER_LEN,
            got,
        });
    };
    let header = Header::check(
        version,
        edge,
        bits,
        reserved,
        u16::from_le_bytes([len_lo, len_hi]),
    )?;
    let volume = header.size.volume();
    let len = usize::from(header.len);
    let data_len = voxel_bytes(volume, header.bits.into());
    let needed = HEADER_LEN + 2 * len + data_len;
    if got < needed {
        return Err(CodecError::Truncated { needed, got });
    }
    if got > needed {
        return Err(CodecError::TrailingBytes {
            extra: got - needed,
        });
    }
    let (palette_bytes, data) = bytes[HEADER_LEN..].split_at(2 * len);
    let palette = read_palette(palette_bytes)?;
    if header.bits == 0 {
        let id = palette.first().copied().ok_or(CodecError::EmptyPalette)?;
        return Ok(PaletteChunk::filled(header.size, id));
    }
    let bits = u32::from(header.bits);
    check_padding(data, volume, bits)?;
    let words = read_words(data, volume, bits);
    if bits == 16 {
        return Ok(PaletteChunk::from_raw_words(header.size, words));
    }
    PaletteChunk::from_indexed_words(header.size, palette, bits, words).map_err(|bad| {
        CodecError::PaletteIndexOutOfRange {
            index: bad.index,
            len: header.len,
            voxel: bad.voxel,
        }
    })
}

/// A header whose fields are each valid and consistent.
struct Header {
    size: ChunkSize,
    bits: u8,
    len: u16,
}

impl Header {
    fn check(version: u8, edge: u8, bits: u8, reserved: u8, len: u16) -> Result<Self, CodecError> {
        if version != CODEC_VERSION {
            return Err(CodecError::UnsupportedVersion(version));
        }
        let size = ChunkSize::from_edge(edge.into()).map_err(|_| CodecError::BadChunkEdge(edge))?;
        let max_len: u16 = match bits {
            0 => 1,
            1 | 2 | 4 | 8 => 1 << bits,
            16 => 0,
            _ => return Err(CodecError::BadBitsPerVoxel(bits)),
        };
        if reserved != 0 {
            return Err(CodecError::NonZeroReserved);
        }
        if len > max_len {
            return Err(CodecError::PaletteTooLarge { len, bits });
        }
        if len == 0 && bits != 16 {
            return Err(CodecError::EmptyPalette);
        }
        Ok(Header { size, bits, len })
    }
}

/// The palette entries, checked to be distinct (at most 256 of them).
fn read_palette(bytes: &[u8]) -> Result<Vec<BlockId>, CodecError> {
    let palette: Vec<BlockId> = bytes
        .chunks_exact(2)
        .map(|b| BlockId(u16::from_le_bytes([b[0], b[1]])))
        .collect();
    let mut sorted = [BlockId::AIR; 256];
    let sorted = &mut sorted[..palette.len().min(256)];
    sorted.copy_from_slice(&palette[..sorted.len()]);
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
        return Err(CodecError::DuplicatePaletteEntry(w[0]));
    }
    Ok(palette)
}

/// Checks that the bits after voxel `volume - 1` in the last byte of `data` are zero.
fn check_padding(data: &[u8], volume: usize, bits: u32) -> Result<(), CodecError> {
    let used = (volume * bits as usize) % 8;
    match data.last() {
        Some(&last) if used != 0 && u64::from(last) & !low_bits(used) != 0 => {
            Err(CodecError::NonZeroPadding)
        }
        _ => Ok(()),
    }
}

/// The voxel bytes as packed words (the tail of the last word zero).
fn read_words(data: &[u8], volume: usize, bits: u32) -> Vec<u64> {
    let mut words = vec![0u64; PackedBits::word_count(volume, bits)];
    for (word, chunk) in words.iter_mut().zip(data.chunks(8)) {
        let mut le = [0u8; 8];
        le[..chunk.len()].copy_from_slice(chunk);
        *word = u64::from_le_bytes(le);
    }
    words
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn padding_bits_past_the_last_voxel_are_rejected() {
        // No supported volume leaves padding, so check the helper on a 3-voxel, 1-bit stream.
        assert_eq!(check_padding(&[0b0000_0101], 3, 1), Ok(()));
        assert_eq!(
            check_padding(&[0b0000_1101], 3, 1),
            Err(CodecError::NonZeroPadding)
        );
        assert_eq!(
            check_padding(&[0xFF, 0b0001_0000], 3, 4),
            Err(CodecError::NonZeroPadding)
        );
        assert_eq!(check_padding(&[0xFF, 0xFF], 4, 4), Ok(()));
    }

    #[test]
    fn every_supported_volume_fills_whole_bytes() {
        for size in ChunkSize::ALL {
            for bits in [1u32, 2, 4, 8, 16] {
                assert_eq!(size.volume() * bits as usize % 8, 0);
            }
        }
    }
}
