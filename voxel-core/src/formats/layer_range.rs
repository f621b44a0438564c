//! Element ranges of a chunk's layers inside the gigabuffer.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};

use super::wgsl::{WgslStruct, WgslType, member};
use super::{FaceDirection, FormatError};

/// A contiguous run of elements in one gigabuffer: `offset..offset + count`, in units of the
/// element type (not bytes). 8 bytes.
///
/// | bytes | field    | type | meaning               |
/// | ----- | -------- | ---- | --------------------- |
/// | 0..4  | `offset` | u32  | first element         |
/// | 4..8  | `count`  | u32  | number of elements    |
///
/// Valid when `offset + count` fits in `u32` (checked by [`MeshedChunkInfo`]).
///
/// [`MeshedChunkInfo`]: super::MeshedChunkInfo
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct LayerRange {
    /// First element.
    pub offset: u32,
    /// Number of elements.
    pub count: u32,
}

const _: () = assert!(size_of::<LayerRange>() == 8, "LayerRange must be 8 bytes");

/// A contiguous run of quads sorted by face direction: the quads facing
/// [`FaceDirection::ALL`]`[i]` come after those of every lower index, `counts[i]` of them.
/// 28 bytes.
///
/// | bytes | field       | type | meaning                                    |
/// | ----- | ----------- | ---- | ------------------------------------------ |
/// | 0..4  | `offset`    | u32  | first element (of face direction 0)        |
/// | 4..28 | `counts[i]` | u32  | elements facing direction `i`, `i` in 0..6 |
///
/// Per-direction counts let the cull pass skip whole directions that face away from the camera
/// (Lum's per-face culling). Valid when `offset + sum(counts)` fits in `u32` (checked by
/// [`MeshedChunkInfo`]).
///
/// [`MeshedChunkInfo`]: super::MeshedChunkInfo
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct FaceLayerRange {
    /// First element (of face direction 0).
    pub offset: u32,
    /// Elements per face direction, in [`FaceDirection`] index order.
    pub counts: [u32; 6],
}

const _: () = assert!(
    size_of::<FaceLayerRange>() == 28,
    "FaceLayerRange must be 28 bytes"
);

impl LayerRange {
    /// The WGSL struct `LayerRange { offset: u32, count: u32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "LayerRange",
        size: size_of::<LayerRange>(),
        members: &[
            member("offset", offset_of!(LayerRange, offset), WgslType::U32),
            member("count", offset_of!(LayerRange, count), WgslType::U32),
        ],
    };

    /// One past the last element, as `u64` (never overflows).
    #[inline]
    pub const fn end(&self) -> u64 {
        self.offset as u64 + self.count as u64
    }

    /// `Ok(())` if [`end`](Self::end) fits in `u32`, else [`FormatError::RangeOverflow`].
    pub fn check(&self, field: &'static str) -> Result<(), FormatError> {
        check_end(field, self.offset, self.count.into())
    }
}

impl FaceLayerRange {
    /// The WGSL struct `FaceLayerRange { offset, count_pos_x, count_neg_x, count_pos_y,
    /// count_neg_y, count_pos_z, count_neg_z: u32 }`.
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "FaceLayerRange",
        size: size_of::<FaceLayerRange>(),
        members: &[
            member("offset", offset_of!(FaceLayerRange, offset), WgslType::U32),
            member("count_pos_x", Self::count_offset(0), WgslType::U32),
            member("count_neg_x", Self::count_offset(1), WgslType::U32),
            member("count_pos_y", Self::count_offset(2), WgslType::U32),
            member("count_neg_y", Self::count_offset(3), WgslType::U32),
            member("count_pos_z", Self::count_offset(4), WgslType::U32),
            member("count_neg_z", Self::count_offset(5), WgslType::U32),
        ],
    };

    const fn count_offset(face: usize) -> usize {
        offset_of!(FaceLayerRange, counts) + face * size_of::<u32>()
    }

    /// All elements of every direction, as `u64` (never overflows).
    pub fn total(&self) -> u64 {
        self.counts.iter().map(|&c| u64::from(c)).sum()
    }

    /// The first element facing `face`: `offset + counts[..face]`, as `u64`.
    pub fn face_start(&self, face: FaceDirection) -> u64 {
        let before: u64 = self.counts[..usize::from(face.index())]
            .iter()
            .map(|&c| u64::from(c))
            .sum();
        u64::from(self.offset) + before
    }

    /// The elements facing `face`, or `None` if their end does not fit in `u32`.
    pub fn face_range(&self, face: FaceDirection) -> Option<LayerRange> {
        let offset = u32::try_from(self.face_start(face)).ok()?;
        let range = LayerRange {
            offset,
            count: self.counts[usize::from(face.index())],
        };
        u32::try_from(range.end()).ok().map(|_| range)
    }

    /// `Ok(())` if `offset + total()` fits in `u32`, else [`FormatError::RangeOverflow`].
    pub fn check(&self, field: &'static str) -> Result<(), FormatError> {
        check_end(field, self.offset, self.total())
    }
}

fn check_end(field: &'static str, offset: u32, count: u64) -> Result<(), FormatError> {
    if u64::from(offset) + count <= u64::from(u32::MAX) {
        Ok(())
    } else {
        Err(FormatError::RangeOverflow {
            field,
            offset,
            count,
        })
    }
}
