//! The two packed states of a [`PaletteChunk`](super::PaletteChunk): palette indices
//! (1/2/4/8 bits per voxel) and raw 16-bit ids, with their reference counts and single-voxel
//! writes.

use alloc::vec::Vec;

use crate::BlockId;

use super::packed_bits::PackedBits;

/// Most palette entries an indexed chunk holds (8-bit indices); one more switches to raw ids.
pub(crate) const MAX_PALETTE: usize = 256;

/// The smallest index width (1, 2, 4 or 8) that addresses `entries` palette entries
/// (`entries <= 256`).
pub(crate) const fn bits_for(entries: usize) -> u32 {
    match entries {
        0..=2 => 1,
        3..=4 => 2,
        5..=16 => 4,
        _ => 8,
    }
}

/// Palette indices. Invariants: every index is `< palette.len() <= 2^bits`, palette ids are
/// distinct, `counts[j]` is the number of voxels holding index `j` (zero for a free entry,
/// which the next new id reuses), `air` is the position of [`BlockId::AIR`] in the palette.
#[derive(Clone, Debug)]
pub(crate) struct Indexed {
    pub(crate) palette: Vec<BlockId>,
    pub(crate) counts: Vec<u32>,
    pub(crate) air: Option<u32>,
    pub(crate) indices: PackedBits,
}

/// Raw 16-bit ids. Invariants: `ids` is sorted and distinct and lists exactly the ids present,
/// `counts[k]` (> 0) is how many voxels hold `ids[k]`.
#[derive(Clone, Debug)]
pub(crate) struct Raw {
    pub(crate) ids: Vec<BlockId>,
    pub(crate) counts: Vec<u32>,
    pub(crate) values: PackedBits,
}

/// What a write to an [`Indexed`] did.
pub(crate) enum IndexedWrite {
    /// Written; `now_uniform` when the new id now covers the whole chunk.
    Done { old: BlockId, now_uniform: bool },
    /// 256 live entries and a 257th id: the chunk must switch to raw ids first.
    NeedsRaw,
}

impl Indexed {
    /// A chunk of `volume` voxels, all `fill` except voxel `i`, which is `id` (`id != fill`).
    pub(crate) fn two_ids(fill: BlockId, id: BlockId, i: usize, volume: usize) -> Indexed {
        let mut indices = PackedBits::zeroed(volume, 1);
        indices.set(i, 1);
        let mut ix = Indexed {
            palette: alloc::vec![fill, id],
            counts: alloc::vec![volume as u32 - 1, 1],
            air: None,
            indices,
        };
        ix.find_air();
        ix
    }

    /// Recomputes `air` from the palette.
    pub(crate) fn find_air(&mut self) {
        self.air = self
            .palette
            .iter()
            .position(|p| p.is_air())
            .map(|j| j as u32);
    }

    /// The id of voxel `i`.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> BlockId {
        self.palette[self.indices.get(i) as usize]
    }

    /// Voxels that are not air.
    pub(crate) fn non_air(&self, volume: usize) -> usize {
        match self.air {
            Some(a) => volume - self.counts[a as usize] as usize,
            None => volume,
        }
    }

    /// Puts `id` in palette slot `j` (a free slot or a new one at the end), keeping `air`.
    fn assign(&mut self, j: usize, id: BlockId) {
        if j == self.palette.len() {
            self.palette.push(id);
            self.counts.push(0);
        } else {
            if self.air == Some(j as u32) {
                self.air = None;
            }
            self.palette[j] = id;
        }
        if id.is_air() {
            self.air = Some(j as u32);
        }
    }

    /// Writes `id` at voxel `i`: reuses its palette entry, or a free one, or appends one
    /// (growing the index width when the palette is full).
    pub(crate) fn set(&mut self, i: usize, id: BlockId, volume: usize) -> IndexedWrite {
        let old_ix = self.indices.get(i) as usize;
        let old = self.palette[old_ix];
        if old == id {
            return IndexedWrite::Done {
                old,
                now_uniform: false,
            };
        }
        let new_ix = match self.palette.iter().position(|&p| p == id) {
            Some(j) => j,
            None => {
                // The voxel being overwritten may be the last of its id: take over its slot.
                let free = if self.counts[old_ix] == 1 {
                    Some(old_ix)
                } else {
                    self.counts.iter().position(|&c| c == 0)
                };
                let j = match free {
                    Some(j) => j,
                    None => {
                        let bits = self.indices.bits();
                        if self.palette.len() >= 1 << bits {
                            if bits >= 8 {
                                return IndexedWrite::NeedsRaw;
                            }
                            self.indices = self.indices.repacked(volume, bits * 2);
                        }
                        self.palette.len()
                    }
                };
                self.assign(j, id);
                j
            }
        };
        self.indices.set(i, new_ix as u32);
        self.counts[old_ix] -= 1;
        self.counts[new_ix] += 1;
        IndexedWrite::Done {
            old,
            now_uniform: self.counts[new_ix] as usize == volume,
        }
    }
}

impl Raw {
    /// The same voxels as raw ids.
    pub(crate) fn from_indexed(ix: &Indexed, volume: usize) -> Raw {
        let mut values = PackedBits::zeroed(volume, 16);
        for i in 0..volume {
            values.set(i, ix.get(i).0.into());
        }
        let mut pairs: Vec<(BlockId, u32)> = ix
            .palette
            .iter()
            .copied()
            .zip(ix.counts.iter().copied())
            .filter(|&(_, c)| c > 0)
            .collect();
        pairs.sort_unstable();
        Raw {
            ids: pairs.iter().map(|p| p.0).collect(),
            counts: pairs.iter().map(|p| p.1).collect(),
            values,
        }
    }

    /// The id of voxel `i`.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> BlockId {
        BlockId(self.values.get(i) as u16)
    }

    /// Voxels that are not air.
    pub(crate) fn non_air(&self, volume: usize) -> usize {
        match self.ids.binary_search(&BlockId::AIR) {
            Ok(k) => volume - self.counts[k] as usize,
            Err(_) => volume,
        }
    }

    /// Writes `id` at voxel `i`; returns the old id and whether `id` now covers the chunk.
    pub(crate) fn set(&mut self, i: usize, id: BlockId, volume: usize) -> (BlockId, bool) {
        let old = self.get(i);
        if old == id {
            return (old, false);
        }
        self.values.set(i, id.0.into());
        if let Ok(k) = self.ids.binary_search(&old) {
            self.counts[k] -= 1;
            if self.counts[k] == 0 {
                self.ids.remove(k);
                self.counts.remove(k);
            }
        }
        let k = match self.ids.binary_search(&id) {
            Ok(k) => k,
            Err(k) => {
                self.ids.insert(k, id);
                self.counts.insert(k, 0);
                k
            }
        };
        self.counts[k] += 1;
        (old, self.counts[k] as usize == volume)
    }
}
