//! The renderer: every resident node (level-0 chunks and coarser LOD nodes) selected by one
//! screen-space error budget on the GPU, drawn as quads or as far blocks, two-phase occlusion
//! culled, into a G-buffer and a 64-bit visibility buffer; deferred lighting, a transparent
//! forward pass, tonemap. One encoder per frame, recorded pass by pass.
//!
//! ```text
//!  upload_chunk ─► residency: Gigabuffer (quads, smooth vertices, smooth quads, draw blocks)
//!                  + MeshedChunkTable + node table
//!
//!  record_frame(encoder) (renderer/record.rs), one file per pass in passes/:
//!    early phase:  cull (LOD selection, frustum, last frame's visibility)
//!                  ─► quad_raster (compute opaque path) │ far_splat / far_raster
//!                  ─► gbuffer (raster opaque quads, smooth quads, raster far draws)
//!    hiz: the depth pyramid from the G-buffer depth and the visibility buffer
//!    late phase:   cull of the rest against the pyramid ─► the same draws for what it adds
//!    grass (with clutter): the chunks the cull drew ─► their clutter units as crossed quads
//!                  into the G-buffer (passes::grass; rules in render_model::grass)
//!    prop cull (glTF props: per instance, frustum and this frame's pyramid) ─► props (one
//!       indexed indirect draw per batch into the G-buffer; see [`props`])
//!    cull transparent (ordered, back to front)
//!    [─► shadow grid ─► shadow trace] (shadows on: the drawn nodes' quads into a bit grid
//!       around the eye, then per pixel the sun and sky rays through it; passes::shadow)
//!    ─► lighting (compute or fragment)
//!    ─► transparent (blended, hidden behind the depth and the visibility buffer)
//!    ─► tonemap ─► Rgba8 sRGB output (read back with read_image; present blits it to a
//!       window)
//! ```
//!
//! The rules the passes follow live without wgpu in `render-model`: level-of-detail selection
//! and its error rule ([`render_model::cull::lod`]), the cull's records and CPU reference,
//! the camera ([`render_model::Camera`], camera-relative: chunk differences in `i32`, small
//! `f32` offsets), the lighting model ([`render_model::lighting`]), the transparent order
//! ([`render_model::transparent`]) and residency under a memory budget
//! ([`render_model::memory_plan`]). Here: the far paths ([`far`]), the passes ([`passes`]),
//! sizing from a scene ([`RendererConfig::fitted`]), and drawing into a host's targets
//! ([`external`]).
//!
//! **CPU work per frame** is the same whatever the number of resident chunks: a few cull
//! records, one multi-draw per layer and page, bind groups made once per set of resources.
//!
//! **Smooth layer bookkeeping.** `MeshedChunkInfo` has a smooth-vertex range but no
//! smooth-quad range: the node table (`NodeRecord`) holds it, and the GPU cull writes one
//! `SmoothDraw` and one indirect draw per visible smooth node. The GPU holds the bytes the
//! mesher measured: a NoCubes or SurfaceNets chunk costs 16 B per vertex + 6, 8 or 16 B per
//! quad (`voxel_core::formats::SmoothQuads`, uploaded as the mesher wrote them, zero-padded to
//! whole words). A NoCubes chunk's cube faces are greedy quads in its opaque layer, drawn with
//! the other quads; the smooth positions use `UnormExtent::padded_lattice`, so pinned vertices
//! land on the quads' integer corners.
//!
//! **Needs** `INDIRECT_FIRST_INSTANCE` (lavapipe and NVIDIA have it): the cull pass's commands
//! name their record through `first_instance`; without it [`Renderer::new`] returns
//! [`RenderError::MissingFeature`]. Both `MultiDrawPath`s and both `TimingPath`s work.
//!
//! **Clutter** is drawn by the grass pass when the configuration asks for it
//! ([`RendererConfig::with_clutter`]): two crossed quads per unit, swaying with
//! [`Renderer::set_time`], faded out by the error budget.
//!
//! **Not drawn:** shadows, voxel textures (glTF props have their base colour textures), the
//! props' emissive term and sorted blending of BLEND props ([`props`]).

mod error;
pub mod external;
pub mod far;
mod fit;
pub mod passes;
pub mod props;
mod renderer;

pub use error::RenderError;
pub use external::{HostDepth, HostError, HostPass, HostTargets};
pub use fit::SceneFootprint;
pub use passes::fullscreen::FullscreenPath;
pub use passes::targets::{FrameImage, RenderTargets};
pub use renderer::{OpaqueChoice, OpaquePath, Renderer, RendererConfig};
