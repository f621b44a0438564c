//! [`Axis`] and [`Facing`]: how each face direction maps onto slices, lines and bits, and
//! which way its faces point.
//!
//! The two faces of an axis (+X and -X, ...) share their slices, lines, bits and quad shifts:
//! those are the constants of [`Axis`], and each axis's walk is compiled once for both its
//! faces. What differs between the two, the front slice's side, the face bits and the AO
//! table, is a [`Facing`], read at run time: one walk for both halves the walks' code, and
//! the second face's walk finds the code in the instruction cache that the first one left.

use voxel_core::formats::PackedQuad;

use super::ao::AO_TABLES;

/// How the faces along axis `A` (0 = x, 1 = y, 2 = z; face directions `2 * A` and `2 * A + 1`
/// of `FaceDirection::ALL`) map onto slices, lines and bits. Everything but the strides is a
/// constant, so each axis's loops are compiled with immediate shifts and offsets.
pub(crate) struct Axis<const A: usize>;

impl<const A: usize> Axis<A> {
    /// Layout index (0 = A, 1 = B, 2 = C).
    pub(super) const LAYOUT: usize = [2, 1, 0][A];
    /// The axes (0 = x, 1 = y, 2 = z) of the slice, line and bit coordinates.
    pub(super) const AXES: [u32; 3] = [[0, 1, 2], [1, 2, 0], [2, 1, 0]][A];
    /// Bit offset, in `PackedQuad` word 0, of the slice coordinate.
    pub(super) const SHIFT_N: u32 = PackedQuad::POSITION_SHIFTS[Self::AXES[0] as usize];
    /// Bit offset in word 0 of the line coordinate.
    pub(super) const SHIFT_L: u32 = PackedQuad::POSITION_SHIFTS[Self::AXES[1] as usize];
    /// Bit offset in word 0 of the bit coordinate.
    pub(super) const SHIFT_B: u32 = PackedQuad::POSITION_SHIFTS[Self::AXES[2] as usize];
    /// Bit offset in word 0 of the quad's extent along lines: its height (the bits run along
    /// every face's width axis).
    pub(super) const SIZE_SHIFT_L: u32 = PackedQuad::HEIGHT_SHIFT;
    /// Bit offset in word 0 of the quad's extent along bits: its width.
    pub(super) const SIZE_SHIFT_B: u32 = PackedQuad::WIDTH_SHIFT;
    /// Grow quads along lines first (`block-mesh`'s order for the ±Y faces; the others grow
    /// along bits first).
    pub(super) const LINES_FIRST: bool = A == 1;
    /// Start quads at the lowest bit, then the lowest line (`block-mesh`'s scan order for the
    /// ±X faces, whose bits run along z); the others start at the lowest line, then bit.
    pub(super) const BIT_MAJOR: bool = A == 0;

    /// Voxel index strides of a step in slice, line and bit, for padded edge `p`.
    #[inline(always)]
    pub(super) fn strides(p: usize) -> [usize; 3] {
        Self::AXES.map(|a| p.pow(a))
    }
}

/// Which of its axis's two faces a face direction is, and what that changes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Facing {
    /// The face direction (index in `FaceDirection::ALL`, 0 to 5).
    pub direction: usize,
    /// True for the positive faces: the front slice is `n + 1`, else `n - 1`.
    pub positive: bool,
    /// The face direction's bits in `PackedQuad` word 1.
    pub face_bits: u32,
    /// AO by 3 x 3 front neighbourhood.
    pub ao_table: &'static [u8; 512],
}

impl Facing {
    /// Face direction `direction` (0 to 5; see `FaceDirection::ALL`).
    #[inline(always)]
    pub(super) const fn of(direction: usize) -> Facing {
        Facing {
            direction,
            positive: direction.is_multiple_of(2),
            face_bits: (direction as u32) << PackedQuad::FACE_SHIFT,
            ao_table: &AO_TABLES[direction],
        }
    }

    /// The front slice of slice `n`.
    #[inline(always)]
    pub(super) fn front(self, n: usize) -> usize {
        if self.positive { n + 1 } else { n - 1 }
    }
}
