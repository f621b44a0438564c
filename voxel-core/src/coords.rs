//! World, chunk and chunk-local coordinates.
//!
//! World block coordinates are `i32` over their whole range. A world position splits into the
//! chunk that holds it and the position inside that chunk by Euclidean division, so negative
//! coordinates land in the right chunk (`-1` is the last voxel of chunk `-1`, not the first of
//! chunk `0`). Every conversion that could leave the `i32` range is checked and returns a
//! [`CoordError`]; nothing wraps silently.
//!
//! ```
//! use voxel_core::{ChunkSize, WorldPos};
//! let (chunk, local) = WorldPos::new(-1, 0, 70).split(ChunkSize::S32);
//! assert_eq!((chunk.x, chunk.y, chunk.z), (-1, 0, 2));
//! assert_eq!((local.x, local.y, local.z), (31, 0, 6));
//! assert_eq!(chunk.world_pos(local, ChunkSize::S32), Ok(WorldPos::new(-1, 0, 70)));
//! ```

use core::fmt;

use crate::ChunkSize;

/// A block position in the world. Any `i32` triple is valid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct WorldPos {
    /// East-west.
    pub x: i32,
    /// Up.
    pub y: i32,
    /// North-south.
    pub z: i32,
}

/// The coordinate of a chunk: world position divided (Euclidean) by the chunk edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ChunkCoord {
    /// Chunk column along x.
    pub x: i32,
    /// Chunk layer along y.
    pub y: i32,
    /// Chunk row along z.
    pub z: i32,
}

/// A voxel position inside one chunk, each axis in `0..edge`.
///
/// Built with [`LocalPos::new`], which checks the axes against a [`ChunkSize`]; storage
/// accessors check it again against their own size, so a position made for a larger chunk is an
/// error, not an out-of-bounds read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LocalPos {
    /// 0..edge.
    pub x: u8,
    /// 0..edge.
    pub y: u8,
    /// 0..edge.
    pub z: u8,
}

/// A coordinate conversion that would leave its valid range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum CoordError {
    /// The chunk's voxels (or the requested one) lie outside the `i32` world range.
    ChunkOutOfWorld {
        /// The chunk asked for.
        chunk: ChunkCoord,
        /// Its edge length.
        edge: u32,
    },
    /// Moving a world position by an offset would leave the `i32` range.
    WorldOverflow {
        /// The starting position.
        pos: WorldPos,
        /// The offset that overflowed.
        offset: [i32; 3],
    },
    /// Moving a chunk coordinate by an offset would leave the `i32` range.
    ChunkOverflow {
        /// The starting chunk.
        chunk: ChunkCoord,
        /// The offset that overflowed.
        offset: [i32; 3],
    },
    /// A local axis is not below the chunk edge.
    LocalOutOfChunk {
        /// The rejected axes.
        pos: [u32; 3],
        /// The chunk edge they must be below.
        edge: u32,
    },
}

impl fmt::Display for CoordError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CoordError::ChunkOutOfWorld { chunk, edge } => write!(
                f,
                "chunk ({}, {}, {}) of edge {edge} lies outside the i32 world range",
                chunk.x, chunk.y, chunk.z
            ),
            CoordError::WorldOverflow { pos, offset } => write!(
                f,
                "world position ({}, {}, {}) moved by {offset:?} overflows i32",
                pos.x, pos.y, pos.z
            ),
            CoordError::ChunkOverflow { chunk, offset } => write!(
                f,
                "chunk ({}, {}, {}) moved by {offset:?} overflows i32",
                chunk.x, chunk.y, chunk.z
            ),
            CoordError::LocalOutOfChunk { pos, edge } => {
                write!(
                    f,
                    "local position {pos:?} is outside a chunk of edge {edge}"
                )
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for CoordError {}

impl WorldPos {
    /// A world position.
    pub const fn new(x: i32, y: i32, z: i32) -> Self {
        WorldPos { x, y, z }
    }

    /// The chunk holding this position and the position inside it. Never fails: Euclidean
    /// division by a positive edge cannot overflow, and the remainder is always in `0..edge`.
    #[inline]
    pub const fn split(self, size: ChunkSize) -> (ChunkCoord, LocalPos) {
        let e = size.edge() as i32;
        let chunk = ChunkCoord {
            x: self.x.div_euclid(e),
            y: self.y.div_euclid(e),
            z: self.z.div_euclid(e),
        };
        let local = LocalPos {
            x: self.x.rem_euclid(e) as u8,
            y: self.y.rem_euclid(e) as u8,
            z: self.z.rem_euclid(e) as u8,
        };
        (chunk, local)
    }

    /// This position moved by `offset`, or an error if any axis leaves the `i32` range.
    pub fn checked_offset(self, offset: [i32; 3]) -> Result<WorldPos, CoordError> {
        let err = CoordError::WorldOverflow { pos: self, offset };
        Ok(WorldPos {
            x: self.x.checked_add(offset[0]).ok_or(err)?,
            y: self.y.checked_add(offset[1]).ok_or(err)?,
            z: self.z.checked_add(offset[2]).ok_or(err)?,
        })
    }
}

impl ChunkCoord {
    /// A chunk coordinate.
    pub const fn new(x: i32, y: i32, z: i32) -> Self {
        ChunkCoord { x, y, z }
    }

    /// The world position of this chunk's voxel `(0, 0, 0)`, or an error if it is outside
    /// the `i32` range.
    pub fn origin(self, size: ChunkSize) -> Result<WorldPos, CoordError> {
        self.world_pos(LocalPos::default(), size)
    }

    /// The world position of a voxel of this chunk, or an error if it is outside the `i32`
    /// range (the last chunks of a non-power-of-two size are only partly inside it) or if
    /// `local` does not fit the chunk.
    pub fn world_pos(self, local: LocalPos, size: ChunkSize) -> Result<WorldPos, CoordError> {
        local.check(size)?;
        let e = size.edge() as i64;
        let axis = |c: i32, l: u8| i32::try_from(c as i64 * e + l as i64).ok();
        let err = CoordError::ChunkOutOfWorld {
            chunk: self,
            edge: size.edge(),
        };
        Ok(WorldPos {
            x: axis(self.x, local.x).ok_or(err)?,
            y: axis(self.y, local.y).ok_or(err)?,
            z: axis(self.z, local.z).ok_or(err)?,
        })
    }

    /// This chunk moved by `offset` chunks, or an error if any axis leaves the `i32` range.
    pub fn checked_offset(self, offset: [i32; 3]) -> Result<ChunkCoord, CoordError> {
        let err = CoordError::ChunkOverflow {
            chunk: self,
            offset,
        };
        Ok(ChunkCoord {
            x: self.x.checked_add(offset[0]).ok_or(err)?,
            y: self.y.checked_add(offset[1]).ok_or(err)?,
            z: self.z.checked_add(offset[2]).ok_or(err)?,
        })
    }

    /// The smallest and largest chunk coordinate (per axis) that holds any `i32` world position.
    pub const fn valid_range(size: ChunkSize) -> (i32, i32) {
        let e = size.edge() as i32;
        (i32::MIN.div_euclid(e), i32::MAX.div_euclid(e))
    }
}

impl LocalPos {
    /// A local position, checked against `size`.
    pub fn new(x: u32, y: u32, z: u32, size: ChunkSize) -> Result<LocalPos, CoordError> {
        let e = size.edge();
        if x >= e || y >= e || z >= e {
            return Err(CoordError::LocalOutOfChunk {
                pos: [x, y, z],
                edge: e,
            });
        }
        Ok(LocalPos {
            x: x as u8,
            y: y as u8,
            z: z as u8,
        })
    }

    /// `Ok(())` if every axis is below `size`'s edge.
    #[inline]
    pub fn check(self, size: ChunkSize) -> Result<(), CoordError> {
        let e = size.edge();
        if u32::from(self.x) >= e || u32::from(self.y) >= e || u32::from(self.z) >= e {
            return Err(CoordError::LocalOutOfChunk {
                pos: [self.x.into(), self.y.into(), self.z.into()],
                edge: e,
            });
        }
        Ok(())
    }

    /// Linear index in a chunk of `size` (x fastest); checks the position first.
    #[inline]
    pub fn index(self, size: ChunkSize) -> Result<usize, CoordError> {
        self.check(size)?;
        Ok(size.linearize(self.x.into(), self.y.into(), self.z.into()))
    }
}
