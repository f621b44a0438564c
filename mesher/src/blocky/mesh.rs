//! [`BlockyMesh`]: the output of the blocky meshers, one [`QuadLayer`] per render pass.

use crate::QuadLayer;

/// Which render pass a layer of a [`BlockyMesh`] belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockyLayer {
    /// Faces of opaque blocks (opaque, clutter-bearing and smoothable classes).
    Opaque,
    /// Faces of transparent blocks (water, glass), drawn after the opaque pass.
    Transparent,
}

/// The quads of one chunk, split into the layers the renderer draws in separate passes.
///
/// Reusable: the meshers [`clear`](Self::clear) it first and keep its capacity. Only non-empty
/// layers count as produced; [`layers`](Self::layers) yields just those, so a chunk without
/// water creates no transparent draw.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BlockyMesh {
    /// Faces of opaque blocks, per face direction.
    pub opaque: QuadLayer,
    /// Faces of transparent blocks, per face direction.
    pub transparent: QuadLayer,
}

impl BlockyMesh {
    /// An empty mesh.
    pub fn new() -> Self {
        Self::default()
    }

    /// Empties both layers, keeping their capacity.
    pub fn clear(&mut self) {
        self.opaque.clear();
        self.transparent.clear();
    }

    /// True when neither layer has a quad.
    pub fn is_empty(&self) -> bool {
        self.opaque.is_empty() && self.transparent.is_empty()
    }

    /// Quads in both layers.
    pub fn len(&self) -> usize {
        self.opaque.len() + self.transparent.len()
    }

    /// The layer for `kind`.
    pub fn layer(&self, kind: BlockyLayer) -> &QuadLayer {
        match kind {
            BlockyLayer::Opaque => &self.opaque,
            BlockyLayer::Transparent => &self.transparent,
        }
    }

    /// The produced layers: the non-empty ones, opaque first.
    pub fn layers(&self) -> impl Iterator<Item = (BlockyLayer, &QuadLayer)> + '_ {
        [BlockyLayer::Opaque, BlockyLayer::Transparent]
            .into_iter()
            .map(|kind| (kind, self.layer(kind)))
            .filter(|(_, layer)| !layer.is_empty())
    }
}
