//! A padded chunk and its palette, decoded from fuzz bytes: the input of every body in this
//! folder (each may read a few bytes of its own first).

use mesher::BlockClasses;
use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, PaddedChunk};

/// Bytes before the voxel bytes.
pub(crate) const HEADER_LEN: usize = 8;

/// The ids that voxel bytes `0xF0..=0xFF` stand for (low nibble): ids past any palette, on both
/// sides of the 64-id boundary of the meshers' cache of known ids and up to the largest `u16`.
pub(crate) const LARGE_IDS: [u16; 16] = [
    63, 64, 65, 69, 70, 71, 100, 255, 256, 1000, 4095, 4096, 30000, 32767, 65534, 65535,
];

/// The chunk size of each value of byte 0's low 3 bits.
pub(crate) const SIZES: [ChunkSize; 8] = [
    ChunkSize::S8,
    ChunkSize::S8,
    ChunkSize::S8,
    ChunkSize::S8,
    ChunkSize::S16,
    ChunkSize::S16,
    ChunkSize::S32,
    ChunkSize::S62,
];

/// The classes palette entries can take (2 bits each).
const CLASSES: [MaterialClass; 4] = [
    MaterialClass::Opaque,
    MaterialClass::Transparent,
    MaterialClass::ClutterBearing,
    MaterialClass::Smoothable,
];

/// How the voxel bytes fill the padded chunk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Fill {
    /// One byte per voxel.
    Voxels,
    /// One byte per cube of `edge^3` voxels (2 or 4): solid blocks, buried voxels, long runs.
    Cells(u32),
    /// Three bytes per `(x, z)` column: height (`byte % (padded edge + 1)` voxels from the
    /// bottom), the id below the top, the id of the top voxel: terrain.
    Columns,
}

/// A padded chunk with its palette, decoded by [`chunk_input`]:
///
/// - byte 0: bits 0-2 the chunk edge ([`SIZES`]: half the values 8, then 16, 16, 32, 62, as
///   checking a 62^3 chunk takes about 500 times as long as an 8^3 one), bits 3-4 the [`Fill`]
///   (voxels, cells of 2^3, cells of 4^3, columns);
/// - byte 1, low 4 bits: palette entries `1..=n` (`n` up to 15, so up to 15 transparent ids,
///   past the 8 the exposure pass compares row by row); bytes 2-5: their classes, 2 bits each;
///   bytes 6-7: bit `i` set when entry `i + 1` emits light;
/// - bytes 8..: the voxel bytes, repeated cyclically (none: all air). A byte below `0xF0` is id
///   `byte % 18` (so ids 16 and 17, and any past the palette, are unknown); the rest are
///   [`LARGE_IDS`].
pub(crate) struct ChunkInput {
    /// The chunk and its one-voxel border.
    pub padded: PaddedChunk,
    /// Its materials.
    pub palette: MaterialPalette,
    /// The palette's classes, as the meshers read them.
    pub classes: BlockClasses,
}

/// The id a voxel byte stands for (see [`ChunkInput`]).
pub(crate) fn voxel_id(byte: u8) -> BlockId {
    if byte >= 0xF0 {
        BlockId(LARGE_IDS[usize::from(byte & 15)])
    } else {
        BlockId(u16::from(byte % 18))
    }
}

/// Decodes a [`ChunkInput`]; `None` for inputs shorter than [`HEADER_LEN`].
pub(crate) fn chunk_input(data: &[u8]) -> Option<ChunkInput> {
    let header = data.get(..HEADER_LEN)?;
    let voxels = &data[HEADER_LEN..];
    let size = SIZES[usize::from(header[0] & 7)];
    let fill = match (header[0] >> 3) & 3 {
        0 => Fill::Voxels,
        1 => Fill::Cells(2),
        2 => Fill::Cells(4),
        _ => Fill::Columns,
    };
    let classes = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
    let emissive = u16::from_le_bytes([header[6], header[7]]);
    let mut palette = MaterialPalette::new();
    for i in 0..u32::from(header[1] & 15) {
        let class = CLASSES[((classes >> (2 * i)) & 3) as usize];
        let mut material = Material::opaque(40 + 13 * i as u8, 90, 200).with_class(class);
        material.emission = if (emissive >> i) & 1 == 1 { 200 } else { 0 };
        palette.push(material).expect("15 entries fit any palette");
    }
    let padded = fill_chunk(size, fill, voxels);
    let classes = BlockClasses::from_palette(&palette);
    Some(ChunkInput {
        padded,
        palette,
        classes,
    })
}

/// The padded chunk of `size` that `bytes` fill in the `fill` layout.
fn fill_chunk(size: ChunkSize, fill: Fill, bytes: &[u8]) -> PaddedChunk {
    if bytes.is_empty() {
        return PaddedChunk::new(size);
    }
    let p = size.padded_edge();
    let byte = |i: usize| bytes[i % bytes.len()];
    PaddedChunk::from_fn(size, |x, y, z| {
        let (x, y, z) = (x as usize, y as usize, z as usize);
        match fill {
            Fill::Voxels => voxel_id(byte(x + p * (y + p * z))),
            Fill::Cells(edge) => {
                let (c, cells) = (edge as usize, p.div_ceil(edge as usize));
                voxel_id(byte(x / c + cells * (y / c + cells * (z / c))))
            }
            Fill::Columns => {
                let column = 3 * (x + p * z);
                let height = usize::from(byte(column)) % (p + 1);
                if y + 1 < height {
                    voxel_id(byte(column + 1))
                } else if y + 1 == height {
                    voxel_id(byte(column + 2))
                } else {
                    BlockId::AIR
                }
            }
        }
    })
}
