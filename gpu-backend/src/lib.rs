//! # gpu-backend
//!
//! The wgpu backend of the voxel meshing stack: it consumes the packed buffers of
//! `voxel-core` (decoding them in WGSL with the formats' own twins, never a re-written copy)
//! and draws them.
//!
//! Built so far (issue 4, first part):
//!
//! - [`device`]: headless and windowed device setup, adapter choice with a clear error, feature
//!   probing with recorded fallbacks ([`GpuCapabilities`]), limits from the adapter;
//! - [`gigabuffer`]: one paged storage buffer per kind of chunk data, sub-allocated with
//!   `offset-allocator`, generation-checked chunk handles, per-frame batched uploads;
//! - [`chunk_table`]: the near (`MeshedChunkInfo`) and far (`ChunkDrawInfo`) chunk tables on the
//!   GPU, written incrementally;
//! - [`shaders`]: WGSL composition on top of `voxel_core::formats::FORMATS_WGSL`, validated
//!   with naga;
//! - [`cull`]: the cull pass (frustum + per-face-direction culling into per-page
//!   multi-draw-indirect commands) and its CPU reference;
//! - [`render`]: the near-field renderer: vertex-pulled greedy and smooth quads into a
//!   G-buffer, deferred lighting, a back-to-front transparent pass and a tonemap, recorded
//!   into one encoder per frame ([`Renderer`]);
//! - [`present`]: a window's swapchain ([`WindowOutput`]) and the pass that copies the
//!   renderer's output into it;
//! - [`timing`]: per-pass GPU time from timestamp queries, CPU wall time as the fallback;
//! - [`readback`] and [`test_support`] for tests.
//!
//! Only the Vulkan backend is compiled (lavapipe in CI, the vendor driver on GPU machines).

mod bind;
pub mod chunk_table;
pub mod cull;
pub mod device;
mod dirty_ranges;
mod fullscreen;
pub mod gigabuffer;
pub mod hiz;
pub mod present;
pub mod readback;
pub mod render;
pub mod shaders;
pub mod test_support;
pub mod timing;

pub use chunk_table::{FarChunkTable, GpuTable, MeshedChunkTable, TableError, TableSlot};
pub use cull::{CullCamera, CullConfig, CullLayer, CullOutput, CullPass};
pub use device::{
    DeviceError, DeviceOptions, GpuCapabilities, GpuContext, MultiDrawPath, TimingPath,
};
pub use gigabuffer::{
    ChunkHandle, ChunkLayersData, ChunkRanges, DataKind, Gigabuffer, GigabufferConfig,
    GigabufferError, UploadedChunk,
};
pub use present::{FrameSkipped, WindowFrame, WindowOutput};
pub use render::{Renderer, RendererConfig};
pub use timing::{GpuTimer, PassTime};
