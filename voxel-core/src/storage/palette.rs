//! [`PaletteChunk`]: palette-compressed chunk storage.

use crate::{BlockId, ChunkSize, CoordError, LocalPos};

use super::packed_bits::low_bits;
use super::palette_repr::{Indexed, IndexedWrite, Raw};
use super::traits::{local_of, row_start};
use super::{StorageError, VoxelStorage};

/// A chunk stored as the smallest of three states:
///
/// | state | per voxel | heap |
/// | --- | --- | --- |
/// | uniform | 0 bits | none: one id held inline, O(1) memory |
/// | indexed | 1, 2, 4 or 8 bits of palette index | indices + palette (2 B per entry) + reference counts (4 B per entry) |
/// | raw | 16 bits: the id itself | ids + a sorted list of the ids present with their counts |
///
/// Indices are packed into `u64` words, `64 / bits` per word, low bits first; no index straddles
/// two words. Each palette entry has a reference count; an entry whose count drops to zero is
/// reused by the next new id. When the palette is full, the next new id widens the indices
/// (1 -> 2 -> 4 -> 8 bits); a 257th id switches to raw 16-bit ids. When one id comes to cover
/// the whole chunk the chunk collapses back to uniform and frees its buffers;
/// [`fill`](VoxelStorage::fill) makes it uniform at once. Widths only grow on writes:
/// [`compact`](PaletteChunk::compact) drops dead entries and re-packs at the smallest width.
///
/// # Occupancy without a mask array
///
/// Unlike [`DenseChunk`](super::DenseChunk), this storage keeps **no** per-row occupancy masks:
/// they would cost one more bit per voxel, and the memory goal is at most 4 bits per voxel plus
/// the palette for a 32^3 chunk of up to 16 ids (16 KiB). Instead
/// [`column_mask`](VoxelStorage::column_mask) derives the exact mask from the packed indices with
/// SWAR word operations: each word is XORed with the air entry's index repeated in every field,
/// a carry trick sets each field's top bit iff the field is non-zero, and a few shift-and-mask
/// steps gather those bits into one bit per voxel. A 62-voxel row costs a handful of word
/// operations per word it touches, and the answer is always up to date because it is computed
/// from the indices themselves. Uniform chunks answer all-ones or zero at once; a palette without
/// air answers all-ones; raw chunks compare each 16-bit field with 0.
///
/// ```
/// use voxel_core::{BlockId, ChunkSize, LocalPos};
/// use voxel_core::storage::{PaletteChunk, VoxelStorage};
///
/// let mut chunk = PaletteChunk::new(ChunkSize::S32);
/// assert_eq!(chunk.heap_bytes(), 0); // uniform air
/// chunk.set(LocalPos::new(4, 0, 0, ChunkSize::S32)?, BlockId(9))?;
/// assert_eq!(chunk.bits_per_voxel(), 1);
/// assert_eq!(chunk.column_mask(0, 0)?, 1 << 4);
/// chunk.fill(BlockId(3));
/// assert_eq!((chunk.bits_per_voxel(), chunk.uniform()), (0, Some(BlockId(3))));
/// # Ok::<(), voxel_core::CoordError>(())
/// ```
#[derive(Clone, Debug)]
pub struct PaletteChunk {
    pub(crate) size: ChunkSize,
    pub(crate) repr: Repr,
}

/// The storage state of a [`PaletteChunk`].
#[derive(Clone, Debug)]
pub(crate) enum Repr {
    Uniform(BlockId),
    Indexed(Indexed),
    Raw(Raw),
}

impl PaletteChunk {
    /// An all-air chunk (uniform: no heap).
    pub const fn new(size: ChunkSize) -> Self {
        Self::filled(size, BlockId::AIR)
    }

    /// A chunk with every voxel `id` (uniform: no heap).
    pub const fn filled(size: ChunkSize, id: BlockId) -> Self {
        PaletteChunk {
            size,
            repr: Repr::Uniform(id),
        }
    }

    /// Bits per voxel: 0 (uniform), 1, 2, 4, 8 (palette indices) or 16 (raw ids).
    pub fn bits_per_voxel(&self) -> u8 {
        match &self.repr {
            Repr::Uniform(_) => 0,
            Repr::Indexed(ix) => ix.indices.bits() as u8,
            Repr::Raw(_) => 16,
        }
    }

    /// The palette that indices refer to: one entry when uniform, none in raw mode. May hold
    /// free entries (ids no voxel uses any more) until [`compact`](Self::compact).
    pub fn palette(&self) -> &[BlockId] {
        match &self.repr {
            Repr::Uniform(id) => core::slice::from_ref(id),
            Repr::Indexed(ix) => &ix.palette,
            Repr::Raw(_) => &[],
        }
    }

    /// The number of distinct ids present in the chunk.
    pub fn distinct_ids(&self) -> usize {
        match &self.repr {
            Repr::Uniform(_) => 1,
            Repr::Indexed(ix) => ix.counts.iter().filter(|&&c| c > 0).count(),
            Repr::Raw(raw) => raw.ids.len(),
        }
    }

    /// The voxel at linear index `i` (`i < volume`, checked by the callers).
    #[inline]
    pub(crate) fn get_index(&self, i: usize) -> BlockId {
        match &self.repr {
            Repr::Uniform(id) => *id,
            Repr::Indexed(ix) => ix.get(i),
            Repr::Raw(raw) => raw.get(i),
        }
    }
}

impl VoxelStorage for PaletteChunk {
    fn new_air(size: ChunkSize) -> Self {
        PaletteChunk::new(size)
    }

    #[inline]
    fn size(&self) -> ChunkSize {
        self.size
    }

    #[inline]
    fn get(&self, pos: LocalPos) -> Result<BlockId, CoordError> {
        Ok(self.get_index(pos.index(self.size)?))
    }

    fn set(&mut self, pos: LocalPos, id: BlockId) -> Result<BlockId, CoordError> {
        let i = pos.index(self.size)?;
        let volume = self.size.volume();
        let (old, now_uniform) = match &mut self.repr {
            Repr::Uniform(fill) => {
                let fill = *fill;
                if fill != id {
                    self.repr = Repr::Indexed(Indexed::two_ids(fill, id, i, volume));
                }
                (fill, false)
            }
            Repr::Indexed(ix) => match ix.set(i, id, volume) {
                IndexedWrite::Done { old, now_uniform } => (old, now_uniform),
                IndexedWrite::NeedsRaw => {
                    let mut raw = Raw::from_indexed(ix, volume);
                    let written = raw.set(i, id, volume);
                    self.repr = Repr::Raw(raw);
                    written
                }
            },
            Repr::Raw(raw) => raw.set(i, id, volume),
        };
        if now_uniform {
            self.repr = Repr::Uniform(id);
        }
        Ok(old)
    }

    fn fill(&mut self, id: BlockId) {
        self.repr = Repr::Uniform(id);
    }

    fn non_air_count(&self) -> usize {
        let volume = self.size.volume();
        match &self.repr {
            Repr::Uniform(id) => {
                if id.is_air() {
                    0
                } else {
                    volume
                }
            }
            Repr::Indexed(ix) => ix.non_air(volume),
            Repr::Raw(raw) => raw.non_air(volume),
        }
    }

    #[inline]
    fn column_mask(&self, y: u32, z: u32) -> Result<u64, CoordError> {
        let start = row_start(self.size, y, z)?;
        let e = self.size.edge_usize();
        Ok(match &self.repr {
            Repr::Uniform(id) if id.is_air() => 0,
            Repr::Uniform(_) => low_bits(e),
            Repr::Indexed(ix) => match ix.air {
                Some(a) => ix.indices.run_not_equal(start, e, a),
                None => low_bits(e),
            },
            Repr::Raw(raw) => raw.values.run_not_equal(start, e, 0),
        })
    }

    #[inline]
    fn copy_row(&self, y: u32, z: u32, out: &mut [BlockId]) -> Result<(), StorageError> {
        let start = row_start(self.size, y, z)?;
        let e = self.size.edge_usize();
        if out.len() != e {
            return Err(StorageError::WrongLength {
                expected: e,
                got: out.len(),
            });
        }
        match &self.repr {
            Repr::Uniform(id) => out.fill(*id),
            Repr::Indexed(ix) if ix.palette.len() <= 16 => {
                // A fixed table indexed with `j & 15` needs no bounds check per voxel.
                let mut table = [BlockId::AIR; 16];
                table[..ix.palette.len()].copy_from_slice(&ix.palette);
                ix.indices
                    .decode_run(start, out, |j| table[j as usize & 15]);
            }
            Repr::Indexed(ix) => {
                let palette = &ix.palette[..];
                ix.indices.decode_run(start, out, |j| {
                    palette.get(j as usize).copied().unwrap_or(BlockId::AIR)
                });
            }
            Repr::Raw(raw) => raw.values.decode_run(start, out, |v| BlockId(v as u16)),
        }
        Ok(())
    }

    fn iter(&self) -> impl Iterator<Item = (LocalPos, BlockId)> + '_ {
        let size = self.size;
        (0..size.volume()).map(move |i| (local_of(size, i), self.get_index(i)))
    }

    fn heap_bytes(&self) -> usize {
        match &self.repr {
            Repr::Uniform(_) => 0,
            Repr::Indexed(ix) => {
                ix.palette.capacity() * size_of::<BlockId>()
                    + ix.counts.capacity() * size_of::<u32>()
                    + ix.indices.heap_bytes()
            }
            Repr::Raw(raw) => {
                raw.ids.capacity() * size_of::<BlockId>()
                    + raw.counts.capacity() * size_of::<u32>()
                    + raw.values.heap_bytes()
            }
        }
    }

    #[inline]
    fn uniform(&self) -> Option<BlockId> {
        match self.repr {
            Repr::Uniform(id) => Some(id),
            _ => None,
        }
    }
}

/// Voxel equality: two chunks are equal when they have the same size and the same id at every
/// position, whatever their widths or palette order.
impl PartialEq for PaletteChunk {
    fn eq(&self, other: &Self) -> bool {
        if self.size != other.size {
            return false;
        }
        if let (Some(a), Some(b)) = (self.uniform(), other.uniform()) {
            return a == b;
        }
        (0..self.size.volume()).all(|i| self.get_index(i) == other.get_index(i))
    }
}

impl Eq for PaletteChunk {}
