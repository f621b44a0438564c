//! Building [`PaletteChunk`]s at their smallest width: from a dense chunk, by compaction, and
//! from decoded parts.

use alloc::vec;
use alloc::vec::Vec;

use crate::{BlockId, ChunkSize};

use super::packed_bits::PackedBits;
use super::palette::{PaletteChunk, Repr};
use super::palette_repr::{Indexed, MAX_PALETTE, Raw, bits_for};
use super::{DenseChunk, VoxelStorage};

/// An index that does not address the palette: `(index, voxel)`.
pub(crate) struct BadIndex {
    pub(crate) index: u32,
    pub(crate) voxel: usize,
}

impl PaletteChunk {
    /// The same voxels at the smallest width that holds them (uniform when one id covers the
    /// chunk, raw 16-bit ids above 256 distinct ids).
    pub fn from_dense(dense: &DenseChunk) -> Self {
        let voxels = dense.as_slice();
        build(voxels.len(), dense.size(), |i| voxels[i])
    }

    /// Drops palette entries no voxel uses and re-packs at the smallest width (uniform, 1, 2,
    /// 4, 8 bits, or raw above 256 distinct ids), releasing spare capacity.
    pub fn compact(&mut self) {
        if matches!(self.repr, Repr::Uniform(_)) {
            return;
        }
        *self = build(self.size.volume(), self.size, |i| self.get_index(i));
    }

    /// An indexed chunk from packed words (the caller checked the word count, the padding,
    /// `palette.len() <= 2^bits` and that palette ids are distinct); fails on the first index
    /// past the palette.
    pub(crate) fn from_indexed_words(
        size: ChunkSize,
        palette: Vec<BlockId>,
        bits: u32,
        words: Vec<u64>,
    ) -> Result<Self, BadIndex> {
        let volume = size.volume();
        let indices = PackedBits::from_words(bits, words);
        let mut counts = vec![0u32; palette.len()];
        for voxel in 0..volume {
            let index = indices.get(voxel);
            match counts.get_mut(index as usize) {
                Some(c) => *c += 1,
                None => return Err(BadIndex { index, voxel }),
            }
        }
        if let Some(j) = counts.iter().position(|&c| c as usize == volume) {
            return Ok(PaletteChunk::filled(size, palette[j]));
        }
        let mut ix = Indexed {
            palette,
            counts,
            air: None,
            indices,
        };
        ix.find_air();
        Ok(PaletteChunk {
            size,
            repr: Repr::Indexed(ix),
        })
    }

    /// A raw chunk from packed 16-bit words (the caller checked the word count).
    pub(crate) fn from_raw_words(size: ChunkSize, words: Vec<u64>) -> Self {
        let values = PackedBits::from_words(16, words);
        let volume = size.volume();
        let (ids, counts) = count_ids((0..volume).map(|i| BlockId(values.get(i) as u16)));
        if let [only] = ids[..] {
            return PaletteChunk::filled(size, only);
        }
        PaletteChunk {
            size,
            repr: Repr::Raw(Raw {
                ids,
                counts,
                values,
            }),
        }
    }
}

impl From<&DenseChunk> for PaletteChunk {
    fn from(value: &DenseChunk) -> Self {
        PaletteChunk::from_dense(value)
    }
}

/// The distinct ids of `all`, sorted, with how often each occurs.
fn count_ids(all: impl Iterator<Item = BlockId>) -> (Vec<BlockId>, Vec<u32>) {
    let mut all: Vec<BlockId> = all.collect();
    all.sort_unstable();
    let mut ids = Vec::new();
    let mut counts: Vec<u32> = Vec::new();
    for id in all {
        match (ids.last(), counts.last_mut()) {
            (Some(&last), Some(c)) if last == id => *c += 1,
            _ => {
                ids.push(id);
                counts.push(1);
            }
        }
    }
    ids.shrink_to_fit();
    counts.shrink_to_fit();
    (ids, counts)
}

/// Palette lookup with a one-entry cache (runs of one id are the common case).
struct Lookup {
    palette: Vec<BlockId>,
    last: Option<(BlockId, usize)>,
}

impl Lookup {
    /// The palette index of `id`, appending it when new; `None` when the palette is full.
    #[inline]
    fn index(&mut self, id: BlockId) -> Option<usize> {
        if let Some((last, j)) = self.last
            && last == id
        {
            return Some(j);
        }
        let j = match self.palette.iter().position(|&p| p == id) {
            Some(j) => j,
            None if self.palette.len() < MAX_PALETTE => {
                self.palette.push(id);
                self.palette.len() - 1
            }
            None => return None,
        };
        self.last = Some((id, j));
        Some(j)
    }
}

/// The chunk of `volume` voxels `at(0..volume)` at its smallest width.
fn build(volume: usize, size: ChunkSize, at: impl Fn(usize) -> BlockId) -> PaletteChunk {
    let mut lookup = Lookup {
        palette: Vec::new(),
        last: None,
    };
    let mut counts: Vec<u32> = Vec::new();
    for i in 0..volume {
        let Some(j) = lookup.index(at(i)) else {
            return build_raw(volume, size, at);
        };
        if j == counts.len() {
            counts.push(0);
        }
        counts[j] += 1;
    }
    let mut palette = lookup.palette;
    if palette.len() <= 1 {
        return PaletteChunk::filled(size, palette.first().copied().unwrap_or(BlockId::AIR));
    }
    let bits = bits_for(palette.len());
    let per = PackedBits::per_word(bits);
    let mut words = vec![0u64; PackedBits::word_count(volume, bits)];
    let mut lookup = Lookup {
        palette,
        last: None,
    };
    for (w, word) in words.iter_mut().enumerate() {
        let mut acc = 0u64;
        for k in 0..per.min(volume - w * per) {
            // Every id was added in the first pass, so the lookup always finds it.
            let j = lookup.index(at(w * per + k)).unwrap_or(0);
            acc |= (j as u64) << (k as u32 * bits);
        }
        *word = acc;
    }
    palette = lookup.palette;
    palette.shrink_to_fit();
    counts.shrink_to_fit();
    let mut ix = Indexed {
        palette,
        counts,
        air: None,
        indices: PackedBits::from_words(bits, words),
    };
    ix.find_air();
    PaletteChunk {
        size,
        repr: Repr::Indexed(ix),
    }
}

/// The chunk of `volume` voxels `at(0..volume)` as raw 16-bit ids.
fn build_raw(volume: usize, size: ChunkSize, at: impl Fn(usize) -> BlockId) -> PaletteChunk {
    let per = PackedBits::per_word(16);
    let mut words = vec![0u64; PackedBits::word_count(volume, 16)];
    for (w, word) in words.iter_mut().enumerate() {
        let mut acc = 0u64;
        for k in 0..per.min(volume - w * per) {
            acc |= u64::from(at(w * per + k).0) << (k * 16);
        }
        *word = acc;
    }
    let (ids, counts) = count_ids((0..volume).map(&at));
    PaletteChunk {
        size,
        repr: Repr::Raw(Raw {
            ids,
            counts,
            values: PackedBits::from_words(16, words),
        }),
    }
}
