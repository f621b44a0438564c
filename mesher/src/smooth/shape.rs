//! [`GridShape`]: the dimensions of a density grid, checked once.

use voxel_core::ChunkSize;
use voxel_core::formats::quantize::UnormExtent;

use crate::MeshError;

/// The number of density samples along x, y and z of a grid stored x fastest
/// (`index = x + dx * (y + dy * z)`).
///
/// A grid of `d` samples per axis has `d - 1` cells per axis and owns the `d - 2` inner samples
/// `1..=d - 2` of each axis (see the
/// [padding contract](super#seamless-chunks-the-padding-contract)): a chunk of `N^3` samples
/// is meshed from a padded grid of `(N + 2)^3` ([`GridShape::padded_chunk`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GridShape {
    dims: [u32; 3],
}

impl GridShape {
    /// Fewest samples per axis: one owned sample between two padding samples.
    pub const MIN_EDGE: u32 = 3;
    /// Most samples per axis. Keeps every linear index, cell index and vertex count far inside
    /// `u32`, and positions at unorm16 steps of at most `1024 / 65535` (0.016 samples).
    pub const MAX_EDGE: u32 = 1024;

    /// A shape of `dims` samples, or [`MeshError::BadShape`] unless every axis is in
    /// `MIN_EDGE..=MAX_EDGE`.
    pub fn new(dims: [u32; 3]) -> Result<GridShape, MeshError> {
        for d in dims {
            if !(Self::MIN_EDGE..=Self::MAX_EDGE).contains(&d) {
                return Err(MeshError::BadShape {
                    reason: "density grid axes must have 3..=1024 samples",
                    value: d as usize,
                });
            }
        }
        Ok(GridShape { dims })
    }

    /// The padded grid of a chunk of `size`: `(edge + 2)^3` samples, the chunk's own samples at
    /// `1..=edge` on each axis (the same layout as [`PaddedChunk`](voxel_core::PaddedChunk)).
    pub const fn padded_chunk(size: ChunkSize) -> GridShape {
        let p = size.edge() + 2;
        GridShape { dims: [p, p, p] }
    }

    /// Samples along x, y, z.
    #[inline]
    pub const fn dims(self) -> [u32; 3] {
        self.dims
    }

    /// Total samples: `dx * dy * dz`.
    #[inline]
    pub const fn sample_count(self) -> usize {
        self.dims[0] as usize * self.dims[1] as usize * self.dims[2] as usize
    }

    /// Linear index of sample `(x, y, z)`: `x + dx * (y + dy * z)`. Does not check the axes.
    #[inline]
    pub const fn index(self, [x, y, z]: [u32; 3]) -> usize {
        let [dx, dy, _] = self.dims;
        x as usize + dx as usize * (y as usize + dy as usize * z as usize)
    }

    /// The sample coordinates of linear index `i` (the inverse of [`index`](Self::index)).
    #[inline]
    pub const fn coords(self, i: usize) -> [u32; 3] {
        let [dx, dy, _] = self.dims;
        let (dx, dy) = (dx as usize, dy as usize);
        [
            (i % dx) as u32,
            (i / dx % dy) as u32,
            (i / (dx * dy)) as u32,
        ]
    }

    /// The unorm16 position extent of packed vertices: the largest axis, in samples. Vertex
    /// positions lie in `0..=largest - 1`, so they always fit; for a padded chunk this is
    /// [`UnormExtent::padded_chunk`] (the `BlockVertex` convention: chunk-local position + 1).
    pub fn extent(self) -> UnormExtent {
        let largest = self.dims[0].max(self.dims[1]).max(self.dims[2]);
        UnormExtent::new(largest as f32).unwrap_or(UnormExtent::UNIT)
    }
}
