//! # render-model
//!
//! The voxel renderer's rules and their CPU twins, without a GPU: what `gpu-backend` computes
//! on the GPU is decided here, in plain Rust, so the CPU reference renderers, the viewer's
//! streamer and the benchmarks use the same rules without linking wgpu (the split follows
//! vello's `vello_encoding`: the CPU half in a crate of its own).
//!
//! - [`antialias`]: FXAA of the final image (the twin of the antialias pass);
//! - [`camera`]: the one camera of the stack (a world voxel plus a fraction, yaw, pitch, field
//!   of view), its camera-relative view-projection and its rays;
//! - [`lighting`]: the lighting model's parameters and its formulas (the WGSL twin lives in
//!   `gpu-backend`'s lighting pass);
//! - [`colour_difference`]: CIELAB and CIEDE2000, how colour tests measure a rendered colour;
//! - [`frame`]: the frame uniforms every renderer shader reads, and the smooth draw record;
//! - [`cull`]: level-of-detail selection by one screen-space error budget ([`cull::lod`]),
//!   the cull's uniforms, node and draw records, and the CPU reference of the cull pass;
//! - [`grass`]: grass clutter as crossed quads: geometry, wind, the fade by the error budget
//!   and the grass pass's records;
//! - [`memory_plan`]: which nodes stay resident under a memory budget;
//! - [`hiz`]: the depth pyramid's levels and the CPU twins of its build and its test;
//! - [`quad_raster`]: the compute rasteriser's records and its CPU reference;
//! - [`transparent`]: the back-to-front order of blended layers;
//! - [`materials`]: the palette as the GPU's material records;
//! - [`pages`]: how a gigabuffer kind is split into pages;
//! - [`props`]: retained glTF prop instances in batches, their GPU records, the
//!   camera-relative rule and the CPU twin of their cull;
//! - [`resident`]: what the renderer records about a resident node.
//!
//! Every `#[repr(C)]` record here has a WGSL twin in `gpu-backend`, whose tests check the
//! layouts against naga's reflection of the shaders.

pub mod antialias;
pub mod camera;
pub mod colour_difference;
pub mod cull;
pub mod frame;
pub mod grass;
pub mod hiz;
pub mod lighting;
pub mod materials;
pub mod memory_plan;
pub mod pages;
pub mod props;
pub mod quad_raster;
pub mod resident;
pub mod transparent;

pub use camera::{Camera, CameraBasis};
pub use lighting::Lighting;
