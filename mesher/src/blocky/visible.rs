//! [`visible_faces`]: one quad per exposed face.

use voxel_core::PaddedChunk;

use super::{BlockyMesh, GreedyMesher};
use crate::{BlockClasses, MeshError};

/// One quad (width = height = 1) per exposed face of `padded`, with per-vertex AO, into `out`
/// (cleared first).
///
/// A face is exposed when the voxel in front of it does not hide it: an opaque voxel hides
/// every face it touches; a transparent voxel shows its faces against air and against other
/// transparent ids, not against its own id (water next to water); an opaque face next to a
/// transparent voxel is shown. Opaque faces go to `out.opaque`, transparent ones to
/// `out.transparent`, each grouped by face direction.
///
/// Fails with [`MeshError::UnknownBlock`] if an exposed face belongs to an id `classes` does
/// not know (`out` is then left empty).
///
/// This allocates a [`GreedyMesher`]'s scratch masks for the one call; to mesh many chunks, keep
/// a mesher and call [`GreedyMesher::visible_faces`].
pub fn visible_faces(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut BlockyMesh,
) -> Result<(), MeshError> {
    GreedyMesher::new().visible_faces(padded, classes, out)
}
