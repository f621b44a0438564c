//! [`Positions`]: the faces of one slice as a flat list of `(line, bit)` positions.
//!
//! On irregular surfaces (terrain) a line holds a handful of faces, and a loop over its bits
//! ends after a count the branch predictor cannot guess: one misprediction per line and per
//! pass. Flattening the lines of a slice into one list first, writing four entries per round
//! whether or not the bits run out, turns the passes that compute keys and emit quads into
//! loops over a list, with one hard-to-predict exit per slice instead of per line.

/// Capacity: every face of a slice (at most 62 x 62 = 3,844) plus the overrun of
/// [`Positions::push_line`]. A power of two, so indices are masked instead of checked.
const LEN: usize = 4096;

/// Positions `l << 6 | b` (line `l`, bit `b`) of faces of one slice, in the order pushed.
#[derive(Clone, Debug)]
pub(crate) struct Positions {
    at: [u16; LEN],
    len: usize,
}

impl Positions {
    /// An empty list.
    pub(crate) fn new() -> Self {
        Positions {
            at: [0; LEN],
            len: 0,
        }
    }

    /// Empties the list.
    #[inline(always)]
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }

    /// Appends the set bits of line `l`, lowest bit first.
    ///
    /// Writes entries four at a time and moves the end only past those that held a bit: the
    /// others are overwritten by the next push, so a line of up to four faces takes no branch
    /// that depends on its bits. (No `count_ones`: the baseline x86-64 target has no `popcnt`.)
    #[inline(always)]
    pub(crate) fn push_line(&mut self, l: usize, mut bits: u64) {
        let tag = (l << 6) as u16;
        let mut i = self.len;
        loop {
            for _ in 0..4 {
                // `| 1 << 63` keeps `trailing_zeros` off its zero case (an entry not kept).
                let b = (bits | 1 << 63).trailing_zeros() as u16;
                self.at[i & (LEN - 1)] = tag | b;
                i += usize::from(bits != 0);
                bits &= bits.wrapping_sub(1);
            }
            if bits == 0 {
                break;
            }
        }
        self.len = i;
    }

    /// The positions pushed since the last [`clear`](Self::clear).
    #[inline(always)]
    pub(crate) fn as_slice(&self) -> &[u16] {
        &self.at[..self.len.min(LEN)]
    }
}

/// The line and bit of a position.
#[inline(always)]
pub(crate) fn line_bit(pos: u16) -> (usize, usize) {
    (usize::from(pos >> 6) & 63, usize::from(pos) & 63)
}

#[cfg(test)]
mod tests {
    use alloc::vec::Vec;

    use super::*;

    #[test]
    fn lists_every_set_bit_in_order() {
        let mut list = Positions::new();
        let lines = [
            (1usize, 0b1011_0000u64),
            (2, 0),
            (5, u64::MAX >> 1),
            (7, 1 << 62),
        ];
        let mut want = Vec::new();
        for &(l, bits) in &lines {
            list.push_line(l, bits);
            want.extend((0..64).filter(|b| bits >> b & 1 == 1).map(|b| (l, b)));
        }
        let got: Vec<_> = list.as_slice().iter().map(|&p| line_bit(p)).collect();
        assert_eq!(got, want);
        list.clear();
        assert!(list.as_slice().is_empty());
    }
}
