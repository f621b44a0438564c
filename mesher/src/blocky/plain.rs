//! The plain-array input: a padded `u16` array as other meshers take it, and its occupancy
//! columns.

use alloc::vec::Vec;

use voxel_core::ChunkSize;

use super::bits::row_non_air;
use crate::MeshError;

/// The padded edge `p` with `p^3 == len`, for the supported chunk sizes.
pub(crate) fn padded_edge_of(len: usize) -> Result<usize, MeshError> {
    ChunkSize::ALL
        .into_iter()
        .map(ChunkSize::padded_edge)
        .find(|p| p * p * p == len)
        .ok_or(MeshError::BadShape {
            reason: "a padded u16 array must hold p^3 ids for p = 10, 18, 34 or 64",
            value: len,
        })
}

/// Occupancy columns of a padded array of edge `p`: `out[y + p * z]` has bit `x` set iff the id
/// at `(x, y, z)` is not air.
#[inline(always)]
pub(crate) fn build_columns(p: usize, voxels: &[u16], out: &mut Vec<u64>) {
    out.clear();
    out.extend(voxels.chunks_exact(p).map(row_non_air));
}
