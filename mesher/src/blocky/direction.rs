//! [`Direction`]: how each face direction maps onto slices, lines and bits.

use voxel_core::formats::PackedQuad;

use super::ao::AO_TABLES;

/// How face direction `D` (index in `FaceDirection::ALL`) maps onto slices, lines and bits.
/// Everything but the strides is a constant, so each direction's loops are compiled with
/// immediate shifts and offsets.
pub(crate) struct Direction<const D: usize>;

impl<const D: usize> Direction<D> {
    /// Layout index (0 = A, 1 = B, 2 = C).
    pub const LAYOUT: usize = [2, 1, 0][D / 2];
    /// True for the positive faces: the front slice is `n + 1`.
    pub const POSITIVE: bool = D.is_multiple_of(2);
    /// The axes (0 = x, 1 = y, 2 = z) of the slice, line and bit coordinates.
    pub const AXES: [u32; 3] = [[0, 1, 2], [1, 2, 0], [2, 1, 0]][D / 2];
    /// Bit offset, in `PackedQuad` word 0, of the slice coordinate.
    pub const SHIFT_N: u32 = PackedQuad::POSITION_SHIFTS[Self::AXES[0] as usize];
    /// Bit offset in word 0 of the line coordinate.
    pub const SHIFT_L: u32 = PackedQuad::POSITION_SHIFTS[Self::AXES[1] as usize];
    /// Bit offset in word 0 of the bit coordinate.
    pub const SHIFT_B: u32 = PackedQuad::POSITION_SHIFTS[Self::AXES[2] as usize];
    /// Bit offset in word 0 of the quad's extent along lines: its height (the bits run along
    /// every face's width axis).
    pub const SIZE_SHIFT_L: u32 = PackedQuad::HEIGHT_SHIFT;
    /// Bit offset in word 0 of the quad's extent along bits: its width.
    pub const SIZE_SHIFT_B: u32 = PackedQuad::WIDTH_SHIFT;
    /// The face direction's bits in `PackedQuad` word 1.
    pub const FACE: u32 = (D as u32) << PackedQuad::FACE_SHIFT;
    /// Grow quads along lines first (`block-mesh`'s order for the ±Y faces; the others grow
    /// along bits first).
    pub const LINES_FIRST: bool = D / 2 == 1;
    /// Start quads at the lowest bit, then the lowest line (`block-mesh`'s scan order for the
    /// ±X faces, whose bits run along z); the others start at the lowest line, then bit.
    pub const BIT_MAJOR: bool = D / 2 == 0;
    /// AO by 3 x 3 front neighbourhood.
    pub const AO_TABLE: &'static [u8; 512] = &AO_TABLES[D];

    /// Voxel index strides of a step in slice, line and bit, for padded edge `p`.
    #[inline(always)]
    pub fn strides(p: usize) -> [usize; 3] {
        Self::AXES.map(|a| p.pow(a))
    }
}
