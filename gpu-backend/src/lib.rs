//! # gpu-backend
//!
//! The wgpu backend of the voxel meshing stack: it consumes the packed buffers of
//! `voxel-core` (decoding them in WGSL with the formats' own twins, never a re-written copy)
//! and draws them.
//!
//! - [`device`]: headless and windowed device setup, adapter choice with a clear error, feature
//!   probing with recorded fallbacks ([`GpuCapabilities`]), limits from the adapter; or a host
//!   engine's own instance, adapter, device and queue adopted with
//!   [`GpuContext::from_wgpu`] (limits checked, missing ones named);
//! - [`gigabuffer`]: one paged storage buffer per kind of chunk data, sub-allocated with
//!   `offset-allocator`, generation-checked chunk handles, per-frame batched uploads;
//! - [`chunk_table`]: the near (`MeshedChunkInfo`) and far (`ChunkDrawInfo`) chunk tables on the
//!   GPU, written incrementally;
//! - [`shaders`]: WGSL composition on top of `voxel_core::formats::FORMATS_WGSL`, validated
//!   with naga;
//! - [`cull`]: the cull pass (frustum, per-face-direction, level-of-detail and two-phase
//!   occlusion culling into multi-draw-indirect commands) and its CPU reference;
//! - [`hiz`]: the depth pyramid the occlusion cull tests against;
//! - [`render`]: the renderer: vertex-pulled greedy and smooth quads into a G-buffer, far
//!   draws, deferred lighting, a back-to-front transparent pass and a tonemap, recorded into
//!   one encoder per frame ([`Renderer`]); [`render::external`] draws its frame into a host's
//!   own colour and depth targets;
//! - [`present`]: a window's swapchain ([`WindowOutput`]) and the pass that copies the
//!   renderer's output into it;
//! - [`pass_chain`]: a frame's consecutive compute steps in one compute pass;
//! - [`timing`]: per-pass GPU time from timestamp queries, CPU wall time as the fallback;
//! - [`png`]: frames as PNG bytes.
//!
//! With the `test-support` feature, `test_support` (a context, or a skip that is loud and fails
//! under `CI=true`) and `readback` (buffer reads) serve the tests of this and other crates;
//! they are not part of the API otherwise.
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
pub mod pass_chain;
pub mod png;
pub mod present;
#[cfg(feature = "test-support")]
pub mod readback;
#[cfg(not(feature = "test-support"))]
mod readback;
pub mod render;
pub mod shaders;
#[cfg(feature = "test-support")]
pub mod test_support;
pub mod timing;
#[cfg(test)]
mod twins;

pub use chunk_table::{FarChunkTable, GpuTable, MeshedChunkTable, TableError, TableSlot};
pub use cull::{CullOutput, CullPass};
pub use device::{
    DeviceError, DeviceOptions, GpuCapabilities, GpuContext, MultiDrawPath, TimingPath,
};
pub use gigabuffer::{ChunkHandle, Gigabuffer, GigabufferConfig, GigabufferError, UploadedChunk};
pub use present::{FrameSkipped, WindowFrame, WindowOutput};
pub use readback::ReadbackError;
pub use render::{Renderer, RendererConfig};
pub use timing::{GpuTimer, PassTime};
