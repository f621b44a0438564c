//! Sizing a renderer from what a scene holds and what the adapter allows, instead of fixed
//! budgets: [`SceneFootprint`] adds up the bytes of every chunk to upload,
//! [`RendererConfig::fitted`] gives each gigabuffer kind that much room plus slack for the
//! allocator.
//!
//! The adapter bounds each kind's pages by its storage binding size (`max_page_bytes`); the
//! draw blocks must fit one page (far draws bind them as one). Video memory in all is not
//! something wgpu reports: a caller with a memory budget plans residency against it
//! ([`memory_plan`](render_model::memory_plan)) and fits the renderer to the planned set.

use voxel_core::formats::{ChunkLayersData, DataKind, PerKind};

#[cfg(doc)]
use crate::render::error::RenderError;
use crate::render::far::FarRequest;
use crate::render::renderer::RendererConfig;
use crate::residency::GigabufferConfig;
use voxel_core::ChunkSize;

/// Allocator slack: 1/16 of each kind plus 64 KiB (fragmentation between chunks of different
/// sizes; measured by the gigabuffer tests' churn at under 1/32).
fn with_slack(bytes: u64) -> u64 {
    bytes + bytes / 16 + (64 << 10)
}

/// The bytes per gigabuffer kind and the chunk count of a set of chunks.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SceneFootprint {
    /// Bytes per kind.
    pub bytes: PerKind<u64>,
    /// Chunks (nodes of every level).
    pub chunks: u32,
}

impl SceneFootprint {
    /// Adds one chunk's layers.
    pub fn add(&mut self, layers: &ChunkLayersData<'_>) {
        let counts = layers.element_counts();
        for kind in DataKind::ALL {
            *self.bytes.get_mut(kind) += counts.get(kind) * u64::from(kind.element_size());
        }
        self.chunks = self.chunks.saturating_add(1);
    }

    /// The bytes of every kind together.
    pub fn total_bytes(&self) -> u64 {
        self.bytes.iter().map(|(_, &b)| b).sum()
    }
}

impl RendererConfig {
    /// A configuration for `width x height`, chunks of `size` and far draws `far`, with room
    /// for `footprint` (plus allocator slack) and its chunk count. What the adapter cannot
    /// hold is refused when the renderer is made or a page is created, naming the kind: draw
    /// blocks past one storage binding ([`RenderError::FarDrawsUnavailable`]), a page the
    /// device runs out of memory for (`GigabufferError::OutOfMemory`).
    pub fn fitted(
        width: u32,
        height: u32,
        size: ChunkSize,
        far: FarRequest,
        footprint: &SceneFootprint,
    ) -> RendererConfig {
        let chunks = footprint.chunks.max(1);
        let mut gigabuffer = GigabufferConfig::empty().with_max_chunks(chunks);
        for kind in DataKind::ALL {
            let bytes = *footprint.bytes.get(kind);
            if bytes > 0 {
                gigabuffer = gigabuffer.with_bytes(kind, with_slack(bytes));
            }
        }
        let mut config = RendererConfig::new(width, height, size);
        config.gigabuffer = gigabuffer;
        config.max_chunks = chunks;
        config.far = far;
        config
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn room_follows_the_footprint() {
        let quads = [voxel_core::formats::PackedQuad::default(); 10];
        let mut layers = ChunkLayersData::default();
        layers.opaque_quads[0] = &quads;
        let mut footprint = SceneFootprint::default();
        footprint.add(&layers);
        footprint.add(&layers);
        assert_eq!(*footprint.bytes.get(DataKind::Quads), 160);
        assert_eq!(footprint.chunks, 2);
        assert_eq!(footprint.total_bytes(), 160);
        let config = RendererConfig::fitted(64, 32, ChunkSize::S16, FarRequest::Off, &footprint);
        assert_eq!(
            *config.gigabuffer.bytes.get(DataKind::Quads),
            with_slack(160)
        );
        assert_eq!(*config.gigabuffer.bytes.get(DataKind::DrawBlocks), 0);
        assert_eq!(config.max_chunks, 2);
        assert_eq!(config.gigabuffer.max_chunks, 2);
    }
}
