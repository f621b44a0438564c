//! [`Edit`]: the shapes a world is changed by, checked before anything is written.

use core::fmt;

use voxel_core::{BlockId, WorldPos};

/// The most voxels one edit may cover (a 256^3 box): larger edits are refused with
/// [`EditError::TooLarge`] instead of stalling the caller.
pub const MAX_EDIT_VOXELS: u64 = 1 << 24;

/// One change to a world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edit {
    /// Writes `id` at one block.
    Block {
        /// The block.
        pos: WorldPos,
        /// What it becomes.
        id: BlockId,
    },
    /// Writes `id` at every block of the box from `min` to `max`, both inclusive.
    Box {
        /// The lowest corner.
        min: WorldPos,
        /// The highest corner (inclusive).
        max: WorldPos,
        /// What the blocks become.
        id: BlockId,
    },
    /// Writes `id` at every block whose centre lies within `radius` of the centre of block
    /// `centre` (`dx^2 + dy^2 + dz^2 <= radius^2` in whole blocks).
    Sphere {
        /// The centre block.
        centre: WorldPos,
        /// The radius in blocks (0 is the centre block alone).
        radius: u32,
        /// What the blocks become.
        id: BlockId,
    },
}

/// Why an edit is refused (nothing of its batch is written).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EditError {
    /// A box whose `min` exceeds its `max` on some axis.
    InvertedBox {
        /// The box's lowest corner.
        min: [i32; 3],
        /// The box's highest corner.
        max: [i32; 3],
    },
    /// A sphere that reaches past the `i32` block range.
    OutsideWorld {
        /// The sphere's centre.
        centre: [i32; 3],
        /// Its radius.
        radius: u32,
    },
    /// An edit over more than [`MAX_EDIT_VOXELS`] voxels.
    TooLarge {
        /// The voxels its bounding box covers.
        voxels: u64,
    },
}

impl fmt::Display for EditError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EditError::InvertedBox { min, max } => {
                write!(f, "box edit from {min:?} to {max:?} has min above max")
            }
            EditError::OutsideWorld { centre, radius } => write!(
                f,
                "sphere edit at {centre:?} of radius {radius} reaches past the i32 block range"
            ),
            EditError::TooLarge { voxels } => write!(
                f,
                "edit covers {voxels} voxels, more than the limit of {MAX_EDIT_VOXELS}"
            ),
        }
    }
}

impl std::error::Error for EditError {}

impl Edit {
    /// The block the edit writes.
    pub fn id(&self) -> BlockId {
        match *self {
            Edit::Block { id, .. } | Edit::Box { id, .. } | Edit::Sphere { id, .. } => id,
        }
    }

    /// The inclusive bounding box of the blocks the edit covers, after checking the edit.
    pub fn bounds(&self) -> Result<(WorldPos, WorldPos), EditError> {
        let (min, max) = match *self {
            Edit::Block { pos, .. } => (pos, pos),
            Edit::Box { min, max, .. } => {
                if min.x > max.x || min.y > max.y || min.z > max.z {
                    return Err(EditError::InvertedBox {
                        min: [min.x, min.y, min.z],
                        max: [max.x, max.y, max.z],
                    });
                }
                (min, max)
            }
            Edit::Sphere { centre, radius, .. } => {
                let c = [centre.x, centre.y, centre.z].map(i64::from);
                let r = i64::from(radius);
                let fits = c
                    .iter()
                    .all(|&v| v - r >= i64::from(i32::MIN) && v + r <= i64::from(i32::MAX));
                if !fits {
                    return Err(EditError::OutsideWorld {
                        centre: [centre.x, centre.y, centre.z],
                        radius,
                    });
                }
                let lo = c.map(|v| (v - r) as i32);
                let hi = c.map(|v| (v + r) as i32);
                (
                    WorldPos::new(lo[0], lo[1], lo[2]),
                    WorldPos::new(hi[0], hi[1], hi[2]),
                )
            }
        };
        let span = |a: i32, b: i32| (i64::from(b) - i64::from(a) + 1) as u64;
        let voxels = span(min.x, max.x)
            .saturating_mul(span(min.y, max.y))
            .saturating_mul(span(min.z, max.z));
        if voxels > MAX_EDIT_VOXELS {
            return Err(EditError::TooLarge { voxels });
        }
        Ok((min, max))
    }

    /// True when the edit covers `pos` (which lies inside [`bounds`](Self::bounds)).
    pub(crate) fn covers(&self, pos: WorldPos) -> bool {
        match *self {
            Edit::Block { .. } | Edit::Box { .. } => true,
            Edit::Sphere { centre, radius, .. } => {
                let d = |a: i32, b: i32| {
                    let v = i64::from(a) - i64::from(b);
                    v * v
                };
                let r = i64::from(radius);
                d(pos.x, centre.x) + d(pos.y, centre.y) + d(pos.z, centre.z) <= r * r
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_edits_are_refused_by_name() {
        let p = WorldPos::new(0, 0, 0);
        let q = WorldPos::new(-1, 0, 0);
        assert!(matches!(
            Edit::Box {
                min: p,
                max: q,
                id: BlockId(1)
            }
            .bounds(),
            Err(EditError::InvertedBox { .. })
        ));
        let edge = WorldPos::new(i32::MAX - 1, 0, 0);
        assert!(matches!(
            Edit::Sphere {
                centre: edge,
                radius: 2,
                id: BlockId(1)
            }
            .bounds(),
            Err(EditError::OutsideWorld { .. })
        ));
        let far = WorldPos::new(1000, 1000, 1000);
        assert!(matches!(
            Edit::Box {
                min: p,
                max: far,
                id: BlockId(1)
            }
            .bounds(),
            Err(EditError::TooLarge {
                voxels: 1_003_003_001
            })
        ));
        let sphere = Edit::Sphere {
            centre: edge,
            radius: 1,
            id: BlockId(1),
        };
        assert_eq!(
            sphere.bounds(),
            Ok((
                WorldPos::new(i32::MAX - 2, -1, -1),
                WorldPos::new(i32::MAX, 1, 1)
            ))
        );
        assert!(sphere.covers(WorldPos::new(i32::MAX, 0, 0)));
        assert!(!sphere.covers(WorldPos::new(i32::MAX, 1, 0)));
    }
}
