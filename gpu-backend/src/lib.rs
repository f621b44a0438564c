//! # gpu-backend
//!
//! The wgpu backend of the voxel meshing stack: it consumes the packed buffers of
//! `voxel-core` (decoding them in WGSL with the formats' own twins, never a re-written copy)
//! and draws them, following the rules `render-model` states without a GPU.
//!
//! - [`device`]: headless and windowed device setup, adapter choice with a clear error, feature
//!   probing with recorded fallbacks ([`GpuCapabilities`]), limits from the adapter; or a host
//!   engine's own instance, adapter, device and queue adopted with
//!   [`GpuContext::from_wgpu`] (limits checked, missing ones named);
//! - [`residency`]: the resident nodes: the [`residency::gigabuffer`] (one paged storage buffer
//!   per kind of node data, sub-allocated with `offset-allocator`, generation-checked handles,
//!   per-frame batched uploads) and the [`residency::chunk_table`]s (`MeshedChunkInfo` and
//!   node records in the same slots, written incrementally);
//! - [`render`]: the renderer ([`Renderer`]): a frame of passes, one file each with its shader
//!   ([`render::passes`]: cull, compute quad raster, far splat and raster far draws, G-buffer,
//!   Hi-Z, lighting, transparent, tonemap, present), recorded into one encoder per frame;
//!   [`render::external`] draws its frame into a host's own colour and depth targets;
//! - [`shaders`]: WGSL composition on top of `voxel_core::formats::FORMATS_WGSL`, validated
//!   with naga;
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
pub mod device;
mod dirty_ranges;
pub mod pass_chain;
pub mod png;
pub mod present;
#[cfg(feature = "test-support")]
pub mod readback;
#[cfg(not(feature = "test-support"))]
#[expect(
    unreachable_pub,
    reason = "its items are public for the test-support feature, which makes the module public"
)]
mod readback;
pub mod render;
pub mod residency;
pub mod shaders;
#[cfg(feature = "test-support")]
pub mod test_support;
pub mod timing;
#[cfg(test)]
mod twins;

pub use device::{
    DeviceError, DeviceOptions, GpuCapabilities, GpuContext, MultiDrawPath, TimingPath,
};
pub use present::{FrameSkipped, WindowFrame, WindowOutput};
pub use readback::ReadbackError;
pub use render::passes::cull::{CullOutput, CullPass};
pub use render::{Renderer, RendererConfig};
pub use residency::{
    ChunkHandle, FarChunkTable, Gigabuffer, GigabufferConfig, GigabufferError, GpuTable,
    MeshedChunkTable, Residency, ResidencyError, TableError, TableSlot, UploadedChunk,
};
pub use timing::{GpuTimer, PassTime};
