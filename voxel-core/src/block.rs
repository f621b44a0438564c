//! Block ids: the 16-bit value stored per voxel.

use bytemuck::{Pod, Zeroable};

/// A block type, stored once per voxel. `0` is air; every other value indexes the
/// [`MaterialPalette`](crate::MaterialPalette).
///
/// `#[repr(transparent)]` over `u16`, so a `&[BlockId]` can be viewed as `&[u16]` with
/// [`bytemuck::cast_slice`] and handed to code that works on plain arrays.
#[repr(transparent)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Pod, Zeroable)]
pub struct BlockId(pub u16);

impl BlockId {
    /// Empty space. Never drawn, never occupied.
    pub const AIR: BlockId = BlockId(0);

    /// True for [`BlockId::AIR`].
    #[inline]
    pub const fn is_air(self) -> bool {
        self.0 == 0
    }
}

impl From<u16> for BlockId {
    fn from(value: u16) -> Self {
        BlockId(value)
    }
}

impl From<BlockId> for u16 {
    fn from(value: BlockId) -> Self {
        value.0
    }
}
