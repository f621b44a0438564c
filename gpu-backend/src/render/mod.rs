//! The near-field renderer: vertex-pulled draw passes into a G-buffer, deferred lighting,
//! transparent forward pass, tonemap, all recorded into one encoder per frame.
//!
//! ```text
//!  upload_chunk ─► Gigabuffer (quads, smooth vertices, smooth quads) + MeshedChunkTable
//!
//!  record_frame(encoder):
//!    flush uploads ─► cull (compute, opaque quads) ─► args + records per page
//!                 ─► cull transparent (compute, ordered: back to front) ─► args + records
//!    gbuffer pass:   multi_draw_indexed_indirect(_count) per quad page   (vs_quad, fs_gbuffer)
//!                    one draw per visible smooth chunk                   (vs_smooth)
//!                    ─► albedo+AO, oct normal+material id, reversed-Z depth
//!    lighting pass:  full screen: sun + hemisphere ambient x AO + emission ─► HDR (Rgba16Float)
//!    transparent:    multi-draw per quad page of the ordered commands, lit and
//!                    alpha-blended into HDR
//!    tonemap:        ACES ─► Rgba8UnormSrgb output (read back with read_image)
//!    timer resolve   (GpuTimer scopes: cull, cull transparent, gbuffer, lighting,
//!                    transparent, tonemap)
//!
//! **CPU work per frame** is the same whatever the number of resident greedy chunks: one
//! cull record per layer, one multi-draw per layer and quad page, a few bind groups. Only
//! smooth (NoCubes) chunks cost CPU per chunk (a frustum test and one draw each).
//! ```
//!
//! **Vertex pulling.** No vertex buffers. A greedy quad ([`PackedQuad`], 8 bytes) becomes 4
//! corners in `vs_quad`: the shared quad index buffer ([`quad_indices`]) gives
//! `vertex_index = 4 * quad + slot`, the cull pass's `base_vertex` puts `quad` in the bound
//! page, and the record at `instance_index` (the command's `first_instance`) holds the chunk.
//! The AO diagonal flip of the mesher (`mesher::blocky::triangle_indices`) is applied by
//! renaming slot `k` to corner `(k + flip) & 3`. Smooth quads (4 indices into the chunk's
//! [`BlockVertex`]es) are expanded with `vertex_index / 6` = quad and
//! `[0, 1, 2, 0, 2, 3][vertex_index % 6]` = corner. They are uploaded as the mesher wrote them
//! (`voxel_core::formats::SmoothQuads`: 6-byte compact records where every quad of the chunk
//! fits, else 4 x u16 or 4 x u32 indices), zero-padded to whole words; the chunk's
//! [`SmoothDraw`] carries the form, and `vs_smooth` reads the corner's index with
//! FORMATS_WGSL's `smooth_quad_word` / `smooth_quad_corner` (a parity test checks them against
//! `SmoothQuads::get` in all three forms). So the GPU holds the bytes the mesher measured: a
//! NoCubes or SurfaceNets chunk costs 16 B per vertex + 6, 8 or 16 B per quad. (A NoCubes
//! chunk's cube faces are greedy quads in its opaque layer, drawn with the other quads; the
//! smooth positions use `UnormExtent::padded_lattice`, so pinned vertices land on the quads'
//! integer corners.)
//!
//! **T-junctions.** Greedy quads of different sizes meet at T-junctions, where the rasterizer
//! can leave pinholes (seen on lavapipe: single sky pixels inside terrain). `vs_quad` grows each
//! opaque quad in its own plane by a hair (1/64 pixel at its distance, at least 1/4096 block)
//! so neighbours overlap. The price is a sliver that thin past convex edges, which a pixel
//! centre hits rarely (the image tests skip depth and colour at creases for that reason; a
//! hair of 1/8192 of the distance, 1/10 pixel at 1080p, flipped a few percent of the pixels of
//! far terrain whose blocks are about a pixel wide). Transparent quads are not grown: an overlap
//! would be blended twice.
//!
//! **Smooth layer bookkeeping.** `MeshedChunkInfo` has a smooth-vertex range but no
//! smooth-quad range, and the cull pass does not cull the smooth layer. Rather than grow the
//! shared 112-byte format, the renderer keeps a side table (the gigabuffer's
//! [`ChunkRanges`](crate::gigabuffer::ChunkRanges) per resident chunk) and writes one
//! [`SmoothDraw`] per smooth chunk in the frustum per frame (culled on the CPU by its box); each is
//! one direct draw.
//!
//! **Camera-relative.** See [`camera`]: chunk differences in `i32`, small `f32` offsets.
//!
//! **Transparent order.** See [`transparent`]: chunks back to front, faces within a chunk
//! unsorted.
//!
//! **Lighting.** See [`lighting`], which also holds the CPU twin of the shading formulas.
//!
//! **Needs** `INDIRECT_FIRST_INSTANCE` (lavapipe and NVIDIA have it): the cull pass's commands
//! name their record through `first_instance`; without it [`Renderer::new`] returns
//! [`RenderError::MissingFeature`]. Both `MultiDrawPath`s and both `TimingPath`s work.
//!
//! **Not yet drawn:** clutter units and draw blocks (stored if uploaded, never drawn), far
//! chunks (raycast sprites), shadows, textures; the smooth layer is frustum-culled on the CPU
//! only (no per-face-direction culling).
//!
//! [`PackedQuad`]: voxel_core::formats::PackedQuad
//! [`BlockVertex`]: voxel_core::formats::BlockVertex
//! [`quad_indices`]: crate::cull::quad_indices

pub mod camera;
mod error;
pub mod external;
pub mod far;
mod fit;
pub mod frame;
pub mod lighting;
pub mod materials;
pub mod memory_plan;
mod pipelines;
pub mod quad_raster;
mod renderer;
mod residency;
pub mod targets;
pub mod transparent;

pub use camera::{CameraBasis, RenderCamera};
pub use error::RenderError;
pub use external::{HostDepth, HostError, HostPass, HostTargets};
pub use fit::SceneFootprint;
pub use frame::{FrameShape, FrameUniforms, SmoothDraw};
pub use lighting::LightingParams;
pub use materials::{GpuMaterial, gpu_materials};
pub use pipelines::FullscreenPath;
pub use quad_raster::OpaquePath;
pub use renderer::{Renderer, RendererConfig};
pub use residency::{ChunkMeshData, SmoothFrame, SmoothRanges, chunk_record, mesh_bounds};
pub use targets::{FrameImage, RenderTargets};
