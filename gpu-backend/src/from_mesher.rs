//! The mesher's output as upload data: borrowed views of `mesher`'s buffers in the
//! [`ChunkLayersData`] form [`Renderer::upload_chunk`](crate::Renderer::upload_chunk) takes.
//! Nothing is copied or re-encoded: the mesher writes the packed formats the GPU reads.

use mesher::ChunkMesh;
use mesher::lod::NodeMesh;
use voxel_core::FaceDirection;

use crate::gigabuffer::ChunkLayersData;

/// The upload view of a meshed chunk's layers: the mesher's buffers as they are (the smooth
/// quads in the form the mesh chose, compact where it fits).
pub fn layers_of(mesh: &ChunkMesh) -> ChunkLayersData<'_> {
    let mut layers = ChunkLayersData {
        smooth_vertices: mesh.smooth.vertices(),
        smooth_quads: mesh.smooth.quads(),
        ..Default::default()
    };
    for face in FaceDirection::ALL {
        let i = usize::from(face.index());
        layers.opaque_quads[i] = mesh.blocky.opaque.face(face);
        layers.transparent_quads[i] = mesh.blocky.transparent.face(face);
    }
    layers
}

/// The upload view of a level-of-detail node ([`NodeMesh`]): its layers as [`layers_of`]
/// gives them, plus its skirts and its far-draw blocks with their hiding mask.
pub fn node_layers(node: &NodeMesh) -> ChunkLayersData<'_> {
    let mut layers = layers_of(&node.mesh);
    for face in FaceDirection::ALL {
        let i = usize::from(face.index());
        layers.opaque_skirts[i] = node.skirts.quads(face);
        layers.draw_block_skirts[i] = node.skirts.blocks(face);
    }
    layers.draw_blocks = &node.blocks;
    layers.hiding_mask = &node.hiding_mask;
    layers.transparent_mask = &node.transparent_mask;
    layers
}
