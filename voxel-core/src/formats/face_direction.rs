//! The six axis-aligned face directions of a voxel.

use super::FormatError;

/// The outward direction of one voxel face.
///
/// The index (`0..6`, in declaration order) is what packed formats store: [`PackedQuad`]
/// keeps it in 3 bits, [`FaceLayerRange`] keeps one count per index, and the GPU culls whole
/// direction groups that face away from the camera.
///
/// Each face has a *width axis* and a *height axis* (the two axes a greedy quad grows along):
///
/// | face       | index | normal       | width axis | height axis |
/// | ---------- | ----- | ------------ | ---------- | ----------- |
/// | `PosX`     | 0     | `( 1, 0, 0)` | z          | y           |
/// | `NegX`     | 1     | `(-1, 0, 0)` | z          | y           |
/// | `PosY`     | 2     | `( 0, 1, 0)` | x          | z           |
/// | `NegY`     | 3     | `( 0,-1, 0)` | x          | z           |
/// | `PosZ`     | 4     | `( 0, 0, 1)` | x          | y           |
/// | `NegZ`     | 5     | `( 0, 0,-1)` | x          | y           |
///
/// [`PackedQuad`]: super::PackedQuad
/// [`FaceLayerRange`]: super::FaceLayerRange
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum FaceDirection {
    /// Facing +x.
    PosX = 0,
    /// Facing -x.
    NegX = 1,
    /// Facing +y (up).
    PosY = 2,
    /// Facing -y (down).
    NegY = 3,
    /// Facing +z.
    PosZ = 4,
    /// Facing -z.
    NegZ = 5,
}

impl FaceDirection {
    /// Every direction, in index order.
    pub const ALL: [FaceDirection; 6] = [
        FaceDirection::PosX,
        FaceDirection::NegX,
        FaceDirection::PosY,
        FaceDirection::NegY,
        FaceDirection::PosZ,
        FaceDirection::NegZ,
    ];

    /// The stored index, `0..6`.
    #[inline]
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The direction with this index, or [`FormatError::InvalidFaceDirection`] for `6..=255`.
    #[inline]
    pub const fn from_index(index: u8) -> Result<FaceDirection, FormatError> {
        match index {
            0 => Ok(FaceDirection::PosX),
            1 => Ok(FaceDirection::NegX),
            2 => Ok(FaceDirection::PosY),
            3 => Ok(FaceDirection::NegY),
            4 => Ok(FaceDirection::PosZ),
            5 => Ok(FaceDirection::NegZ),
            value => Err(FormatError::InvalidFaceDirection { value }),
        }
    }

    /// The axis the normal runs along: 0 = x, 1 = y, 2 = z.
    #[inline]
    pub const fn normal_axis(self) -> usize {
        self as usize / 2
    }

    /// True for `PosX`, `PosY`, `PosZ`.
    #[inline]
    pub const fn is_positive(self) -> bool {
        self as u8 & 1 == 0
    }

    /// The unit outward normal.
    #[inline]
    pub const fn normal(self) -> [i32; 3] {
        let mut n = [0; 3];
        n[self.normal_axis()] = if self.is_positive() { 1 } else { -1 };
        n
    }

    /// The axis a quad's width runs along (see the table above): 0 = x, 1 = y, 2 = z.
    #[inline]
    pub const fn width_axis(self) -> usize {
        match self.normal_axis() {
            0 => 2,
            _ => 0,
        }
    }

    /// The axis a quad's height runs along (see the table above): 0 = x, 1 = y, 2 = z.
    #[inline]
    pub const fn height_axis(self) -> usize {
        match self.normal_axis() {
            1 => 2,
            _ => 1,
        }
    }

    /// The direction facing the other way.
    #[inline]
    pub const fn opposite(self) -> FaceDirection {
        match self {
            FaceDirection::PosX => FaceDirection::NegX,
            FaceDirection::NegX => FaceDirection::PosX,
            FaceDirection::PosY => FaceDirection::NegY,
            FaceDirection::NegY => FaceDirection::PosY,
            FaceDirection::PosZ => FaceDirection::NegZ,
            FaceDirection::NegZ => FaceDirection::PosZ,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_normals_and_axes_agree() {
        for (i, face) in FaceDirection::ALL.into_iter().enumerate() {
            assert_eq!(usize::from(face.index()), i);
            assert_eq!(FaceDirection::from_index(i as u8), Ok(face));
            let n = face.normal();
            assert_eq!(n.iter().map(|c| c.abs()).sum::<i32>(), 1);
            assert_eq!(
                n[face.normal_axis()],
                if face.is_positive() { 1 } else { -1 }
            );
            let mut axes = [face.normal_axis(), face.width_axis(), face.height_axis()];
            axes.sort_unstable();
            assert_eq!(axes, [0, 1, 2], "{face:?}");
            assert_eq!(face.opposite().opposite(), face);
            assert_eq!(face.opposite().normal(), n.map(|c| -c));
        }
        for bad in 6..=255u8 {
            assert_eq!(
                FaceDirection::from_index(bad),
                Err(FormatError::InvalidFaceDirection { value: bad })
            );
        }
    }
}
