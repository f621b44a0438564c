//! [`NeighbourhoodMemo`]: the AO split of the last lines of lone faces met, so periodic slices
//! (a checkerboard's) skip the bit-plane comparisons of a line that repeats an earlier one.

use super::masks::Front;

/// The front voxels a line's AO split is computed from: its 3 front lines here, its 9 bit
/// planes in [`super::lone_x`].
pub(crate) trait FrontVoxels: Copy {
    /// A value no line has in an entry with first bit 64 (never matched).
    const NONE: Self;
    /// Equal front voxels. Written as one OR of XORs for the planes: an array comparison
    /// compiles to a call.
    fn same_as(&self, other: &Self) -> bool;
}

impl FrontVoxels for Front {
    const NONE: Self = (0, 0, 0);

    #[inline(always)]
    fn same_as(&self, other: &Self) -> bool {
        ((self.0 ^ other.0) | (self.1 ^ other.1) | (self.2 ^ other.2)) == 0
    }
}

impl FrontVoxels for [u64; 9] {
    const NONE: Self = [0; 9];

    #[inline(always)]
    fn same_as(&self, other: &Self) -> bool {
        self.iter()
            .zip(other)
            .fold(0, |differ, (a, b)| differ | (a ^ b))
            == 0
    }
}

/// The AO split of the last two lines of lone faces met: the bits whose front neighbourhood
/// equals that of the line's first face, and that face's AO byte, by front voxels and first
/// bit. Two entries, because periodic slices (a checkerboard's, or stripes) repeat their lines
/// every other line; a hit saves the 9 bit-plane comparisons, a large share of the work on
/// such slices.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NeighbourhoodMemo<F> {
    /// Front voxels, first bit (64: an empty entry), same-neighbourhood bits, AO byte.
    entries: [(F, usize, u64, u32); 2],
    /// The entry the next miss replaces (0 or 1).
    next: bool,
}

impl<F: FrontVoxels> NeighbourhoodMemo<F> {
    /// No entry.
    pub(crate) fn new() -> Self {
        NeighbourhoodMemo {
            entries: [(F::NONE, 64, 0, 0); 2],
            next: false,
        }
    }

    /// The split for front voxels `front` and first bit `b0`, from an entry or from `compute`.
    #[inline(always)]
    pub(crate) fn split(
        &mut self,
        front: &F,
        b0: usize,
        compute: impl FnOnce() -> (u64, u32),
    ) -> (u64, u32) {
        for (f, b, same, ao) in &self.entries {
            if *b == b0 && f.same_as(front) {
                return (*same, *ao);
            }
        }
        let (same, ao) = compute();
        self.entries[usize::from(self.next)] = (*front, b0, same, ao);
        self.next = !self.next;
        (same, ao)
    }
}
