//! What the rasteriser counted ([`QuadRasterStats`]), read from its state buffer.

use super::layout::StateWord;

/// The rasteriser's counters. The statistics add up over records until
/// `gpu_backend`'s `QuadRaster::clear_stats`; `tiles` and `big_entries` are
/// the last record's list lengths.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QuadRasterStats {
    /// Quads read from the drawn commands.
    pub quads: u32,
    /// Quads with a non-empty pixel box (front-facing, past the near plane, on screen).
    pub visible: u32,
    /// Pixel centres tested by the quads pass (small quads and overflowed big ones).
    pub local_pixels: u32,
    /// Quads drawn through the tile list.
    pub big: u32,
    /// Big quads the tile list had no room for, drawn by the quads pass instead (slow for
    /// large quads; raise `QuadRasterConfig::tile_capacity` if this is not 0).
    pub overflow: u32,
    /// Pixel centres tested by the tiles pass.
    pub tile_pixels: u32,
    /// Pixel centres that hit a quad (visibility words written).
    pub hits: u32,
    /// Tile entries of the last record.
    pub tiles: u32,
    /// Big-quad entries of the last record.
    pub big_entries: u32,
}

impl QuadRasterStats {
    /// The counters from the state words (missing words read 0).
    pub fn from_words(words: &[u32]) -> QuadRasterStats {
        let w = |word: StateWord| words.get(word as usize).copied().unwrap_or(0);
        QuadRasterStats {
            quads: w(StateWord::Quads),
            visible: w(StateWord::Visible),
            local_pixels: w(StateWord::LocalPixels),
            big: w(StateWord::Big),
            overflow: w(StateWord::Overflow),
            tile_pixels: w(StateWord::TilePixels),
            hits: w(StateWord::Hits),
            tiles: w(StateWord::TileCount),
            big_entries: w(StateWord::BigCount),
        }
    }

    /// Pixel centres tested in all.
    pub fn tested_pixels(&self) -> u64 {
        u64::from(self.local_pixels) + u64::from(self.tile_pixels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_map_to_fields() {
        let words: Vec<u32> = (0..16).map(|i| 100 + i).collect();
        let s = QuadRasterStats::from_words(&words);
        assert_eq!(
            s,
            QuadRasterStats {
                quads: 108,
                visible: 109,
                local_pixels: 110,
                big: 111,
                overflow: 112,
                tile_pixels: 113,
                hits: 114,
                tiles: 100,
                big_entries: 101,
            }
        );
        assert_eq!(s.tested_pixels(), 223);
        assert_eq!(QuadRasterStats::from_words(&[]), QuadRasterStats::default());
    }
}
