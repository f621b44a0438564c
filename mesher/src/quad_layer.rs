//! Quads of one layer, grouped by face direction.

use alloc::vec::Vec;

use voxel_core::FaceDirection;
use voxel_core::formats::PackedQuad;

/// The quads of one layer (opaque or transparent) of a chunk, one list per face direction in
/// [`FaceDirection::ALL`] order. Grouping by direction lets the GPU skip whole groups that face
/// away from the camera (per-face-direction culling), and maps one to one onto
/// `FaceLayerRange::counts` when the layer is uploaded as one contiguous range.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct QuadLayer {
    /// Quads per face direction, indexed by [`FaceDirection::index`].
    pub faces: [Vec<PackedQuad>; 6],
}

impl QuadLayer {
    /// Empties every direction, keeping capacity.
    pub fn clear(&mut self) {
        self.faces.iter_mut().for_each(Vec::clear);
    }

    /// Quads in all directions.
    pub fn len(&self) -> usize {
        self.faces.iter().map(Vec::len).sum()
    }

    /// True when no direction has a quad.
    pub fn is_empty(&self) -> bool {
        self.faces.iter().all(Vec::is_empty)
    }

    /// The quads facing `face`.
    pub fn face(&self, face: FaceDirection) -> &[PackedQuad] {
        &self.faces[usize::from(face.index())]
    }

    /// Quad counts per direction, as `FaceLayerRange::counts` wants them.
    pub fn counts(&self) -> [u32; 6] {
        core::array::from_fn(|i| self.faces[i].len() as u32)
    }

    /// All quads, direction by direction: the order in which the layer is uploaded.
    pub fn iter(&self) -> impl Iterator<Item = &PackedQuad> + '_ {
        self.faces.iter().flatten()
    }
}
