//! The renderer: every resident node (level-0 chunks and coarser LOD nodes) selected by one
//! screen-space error budget on the GPU, drawn as quads or as far blocks, two-phase occlusion
//! culled, into a G-buffer and a 64-bit visibility buffer; deferred lighting, a transparent
//! forward pass, tonemap. One encoder per frame.
//!
//! ```text
//!  upload_chunk ─► Gigabuffer (quads, smooth vertices, smooth quads, draw blocks)
//!                  + MeshedChunkTable + node table
//!
//!  record_frame(encoder), see renderer::record:
//!    early phase:  cull (LOD selection, frustum, last frame's visibility)
//!                  ─► quad raster (compute opaque path) │ far splat / raster far draws
//!                  ─► G-buffer pass (raster opaque quads, smooth quads, raster far draws)
//!    depth pyramid from the G-buffer depth and the visibility buffer
//!    late phase:   cull of the rest against the pyramid ─► the same draws for what it adds
//!    cull transparent (ordered, back to front) ─► lighting (compute or fragment)
//!    ─► transparent pass (blended, hidden behind the depth and the visibility buffer)
//!    ─► tonemap ─► Rgba8 sRGB output (read back with read_image)
//! ```
//!
//! Level-of-detail selection and its error rule are in [`cull::lod`](crate::cull::lod), the far
//! draws in [`far`], the compute rasteriser of opaque quads in [`quad_raster`], residency under
//! a memory budget in [`memory_plan`], sizing from a scene in [`RendererConfig::fitted`].
//!
//! **CPU work per frame** is the same whatever the number of resident chunks: a few cull
//! records, one multi-draw per layer and page, bind groups made once per set of resources.
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
//! smooth-quad range: the node table ([`NodeRecord`](crate::cull::NodeRecord)) holds it, and the
//! GPU cull writes one [`SmoothDraw`] and one indirect draw per visible smooth node.
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
//! **Not yet drawn:** clutter units, shadows, textures.
//!
//! [`PackedQuad`]: voxel_core::formats::PackedQuad
//! [`BlockVertex`]: voxel_core::formats::BlockVertex
//! [`quad_indices`]: crate::cull::quad_indices

mod error;
pub mod external;
pub mod far;
mod fit;
mod pipelines;
pub mod quad_raster;
mod renderer;
pub mod targets;

pub use error::RenderError;
pub use external::{HostDepth, HostError, HostPass, HostTargets};
pub use fit::SceneFootprint;
pub use pipelines::FullscreenPath;
pub use quad_raster::OpaquePath;
pub use renderer::{OpaqueChoice, Renderer, RendererConfig};
pub use targets::{FrameImage, RenderTargets};
