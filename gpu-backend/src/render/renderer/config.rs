//! How a [`Renderer`](super::Renderer) is sized and which paths it draws with.

use render_model::resident::SmoothFrame;
use voxel_core::ChunkSize;
use voxel_core::formats::DataKind;

use crate::render::far::FarRequest;
use crate::render::passes::fullscreen::FullscreenPath;
use crate::residency::GigabufferConfig;

/// How a [`Renderer`](super::Renderer) is sized.
#[derive(Clone, Debug, PartialEq)]
pub struct RendererConfig {
    /// Output width, pixels.
    pub width: u32,
    /// Output height, pixels.
    pub height: u32,
    /// Edge of every chunk.
    pub chunk_size: ChunkSize,
    /// Gigabuffer budget per kind.
    pub gigabuffer: GigabufferConfig,
    /// Resident chunks at most (the chunk table's capacity).
    pub max_chunks: u32,
    /// How smooth vertex positions map to chunk-local blocks.
    pub smooth: SmoothFrame,
    /// Far draws: which path (see [`far`](crate::render::far)); far draws also need space for
    /// draw blocks in `gigabuffer` and level-of-detail selection
    /// ([`Renderer::set_lod`](super::Renderer::set_lod)).
    pub far: FarRequest,
    /// How the full-screen passes run.
    pub fullscreen: FullscreenPath,
    /// How the opaque greedy quads are drawn ([`OpaquePath::Compute`] needs 64-bit atomics
    /// and brings the splat's visibility buffers whatever the far path).
    pub opaque: OpaquePath,
    /// Two-phase occlusion culling against a depth pyramid (see [`crate::render::passes::hiz`]): the nodes
    /// visible last frame are drawn first, the pyramid built from their depth, then every other
    /// node tested against it.
    pub occlusion: bool,
    /// Edges anti-aliased by the antialias pass (FXAA, `render_model::antialias`).
    pub antialias: bool,
    /// Clutter units are drawn as grass (the grass pass, [`crate::render::passes::grass`]);
    /// needs clutter space in `gigabuffer` ([`with_clutter`](Self::with_clutter)). Without it
    /// the pass and its pipelines are not created.
    pub clutter: bool,
    /// Nodes' shell runs are drawn (the shell pass, [`crate::render::passes::shells`]); needs
    /// shell space in `gigabuffer` ([`with_shells`](Self::with_shells)). Without it the pass
    /// and its pipelines are not created.
    pub shells: bool,
}

impl RendererConfig {
    /// A configuration for `width x height` and chunks of `size`: 64 MiB of greedy quads,
    /// 16 MiB each of smooth vertices and quads, 4096 chunks, no far draws, no clutter. Draw
    /// blocks get space with [`with_far`](Self::with_far), clutter with
    /// [`with_clutter`](Self::with_clutter).
    pub fn new(width: u32, height: u32, size: ChunkSize) -> RendererConfig {
        const MIB: u64 = 1 << 20;
        RendererConfig {
            width,
            height,
            chunk_size: size,
            gigabuffer: GigabufferConfig::empty()
                .with_bytes(DataKind::Quads, 64 * MIB)
                .with_bytes(DataKind::SmoothVertices, 16 * MIB)
                .with_bytes(DataKind::SmoothQuads, 16 * MIB)
                .with_max_chunks(4096),
            max_chunks: 4096,
            smooth: SmoothFrame::nocubes(size),
            far: FarRequest::Off,
            fullscreen: FullscreenPath::default(),
            opaque: OpaquePath::default(),
            occlusion: true,
            antialias: true,
            clutter: false,
            shells: false,
        }
    }

    /// This configuration with far draws `far` and `draw_block_bytes` of draw-block space.
    pub fn with_far(mut self, far: FarRequest, draw_block_bytes: u64) -> RendererConfig {
        self.far = far;
        self.gigabuffer = self
            .gigabuffer
            .with_bytes(DataKind::DrawBlocks, draw_block_bytes);
        self
    }

    /// This configuration drawing clutter as grass, with `clutter_bytes` of clutter space (one
    /// gigabuffer page: the grass pass binds it whole).
    pub fn with_clutter(mut self, clutter_bytes: u64) -> RendererConfig {
        self.clutter = true;
        self.gigabuffer = self.gigabuffer.with_bytes(DataKind::Clutter, clutter_bytes);
        self
    }

    /// This configuration drawing shell runs, with `shell_bytes` of shell space (one
    /// gigabuffer page: the shell pass binds it whole).
    pub fn with_shells(mut self, shell_bytes: u64) -> RendererConfig {
        self.shells = true;
        self.gigabuffer = self.gigabuffer.with_bytes(DataKind::Shells, shell_bytes);
        self
    }
}

/// How the renderer draws the opaque greedy quads of meshed nodes: the choice is the GPU's
/// (BENCHMARKS.md has both paths measured on the GPU machine).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum OpaquePath {
    /// The G-buffer raster pass (multi-draw indirect): fastest where raster units are many
    /// (consumer GPUs).
    #[default]
    Raster,
    /// This compute rasteriser into the visibility buffer: for compute-heavy GPUs with few
    /// raster units. Needs 64-bit atomic min/max.
    Compute,
    /// Both paths are built (the compute one only where the device has 64-bit atomic
    /// min/max) and the raster one draws until
    /// [`Renderer::measure_opaque_paths`](super::Renderer::measure_opaque_paths)
    /// keeps the faster on this GPU, or [`Renderer::set_opaque_path`](super::Renderer::set_opaque_path)
    /// picks one.
    Auto,
}
