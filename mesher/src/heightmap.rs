//! Heightmap tiles (SBgl): each `(x, z)` column of voxels reduced to one [`HeightColumn`], its
//! top opaque block's height and id plus the id below it (the side colour under the top block).
//!
//! Only the top opaque surface is kept: caves, overhangs and anything under the top block are
//! not representable, and transparent blocks (water) are skipped, left to the transparent
//! greedy quads.

use alloc::vec::Vec;
use core::fmt;
use voxel_core::BlockId;
pub use voxel_core::formats::{HeightColumn, HeightColumnFields};

/// Why a heightmap tile could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeightmapError {
    /// The voxel slice does not hold `width * width * height` voxels.
    WrongVoxelCount {
        /// Voxels expected.
        expected: usize,
        /// Voxels given.
        actual: usize,
    },
    /// The column height does not fit [`HeightColumn::MAX_HEIGHT`].
    HeightOutOfRange {
        /// The rejected height.
        height: u32,
    },
}

impl fmt::Display for HeightmapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::WrongVoxelCount { expected, actual } => {
                write!(f, "heightmap tile needs {expected} voxels, got {actual}")
            }
            Self::HeightOutOfRange { height } => write!(
                f,
                "heightmap column height {height} is above {}",
                HeightColumn::MAX_HEIGHT
            ),
        }
    }
}

/// Builds one tile's columns, in `x + width * z` order, from `voxels` indexed
/// `x + width * (z + width * y)` (`width` columns each way, `height` voxels tall). A column
/// without an opaque voxel has height 0. `opaque` tells which ids form the ground.
pub fn heightmap_tile(
    width: usize,
    height: usize,
    voxels: &[BlockId],
    opaque: impl Fn(BlockId) -> bool,
) -> Result<Vec<HeightColumn>, HeightmapError> {
    let expected = width * width * height;
    if voxels.len() != expected {
        return Err(HeightmapError::WrongVoxelCount {
            expected,
            actual: voxels.len(),
        });
    }
    let at = |x: usize, y: usize, z: usize| voxels[x + width * (z + width * y)];
    let mut columns = Vec::with_capacity(width * width);
    for z in 0..width {
        for x in 0..width {
            let top_y = (0..height).rev().find(|&y| opaque(at(x, y, z)));
            let fields = match top_y {
                None => HeightColumnFields::default(),
                Some(y) => {
                    let top = at(x, y, z);
                    let under = if y > 0 && opaque(at(x, y - 1, z)) {
                        at(x, y - 1, z)
                    } else {
                        top
                    };
                    let h = u32::try_from(y + 1)
                        .map_err(|_| HeightmapError::HeightOutOfRange { height: u32::MAX })?;
                    HeightColumnFields {
                        height: h,
                        top,
                        under,
                    }
                }
            };
            columns.push(HeightColumn::encode(&fields).map_err(|_| {
                HeightmapError::HeightOutOfRange {
                    height: fields.height,
                }
            })?);
        }
    }
    Ok(columns)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_top_and_under_ids_and_skips_water() {
        const AIR: BlockId = BlockId(0);
        const STONE: BlockId = BlockId(1);
        const GRASS: BlockId = BlockId(2);
        const WATER: BlockId = BlockId(3);
        let (w, h) = (2, 4);
        let mut v = alloc::vec![AIR; w * w * h];
        let idx = |x: usize, y: usize, z: usize| x + w * (z + w * y);
        v[idx(0, 0, 0)] = STONE;
        v[idx(0, 1, 0)] = GRASS;
        v[idx(1, 0, 0)] = STONE;
        v[idx(1, 1, 0)] = WATER;
        let cols = heightmap_tile(w, h, &v, |b| b == STONE || b == GRASS).unwrap();
        let f: Vec<_> = cols.iter().map(|c| c.decode().unwrap()).collect();
        assert_eq!((f[0].height, f[0].top, f[0].under), (2, GRASS, STONE));
        assert_eq!((f[1].height, f[1].top, f[1].under), (1, STONE, STONE));
        assert_eq!(f[2].height, 0);
        assert_eq!(
            heightmap_tile(w, h, &v[1..], |_| true),
            Err(HeightmapError::WrongVoxelCount {
                expected: 16,
                actual: 15
            })
        );
    }
}
