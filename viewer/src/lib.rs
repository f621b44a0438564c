//! # viewer
//!
//! Shows voxel scenes: the built-in procedural terrain, streamed around the camera
//! ([`stream`], seen through a [`view::StreamedView`]), fixed squares of it and MagicaVoxel
//! `.vox` models ([`scene`]), in a window ([`window`]: winit, egui, the GPU renderer, the
//! overlay's [`controls`], [`screenshot`]s) or, without a display, to a PNG file: from the GPU
//! renderer ([`gpu_view`], [`headless`]) when a Vulkan adapter exists (lavapipe counts), else
//! from the CPU reference raycaster ([`reference_raycast`]). [`flight`] flies a scripted path
//! over the streamed terrain and measures its frames.
//!
//! The CPU references (the crate `voxel-reference`, re-exported here) are the ground truth of
//! the GPU image tests: [`reference_raycast`] (one ray per pixel through the voxels) and
//! [`deferred_reference`] (the same rays shaded with the GPU's lighting model). Both renderers
//! and the GPU path share `render_model`'s camera and lighting.

pub mod controls;
pub mod edits;
pub mod flight;
pub mod gpu_view;
pub mod headless;
pub mod pass_times;
pub mod props;
pub mod scene;
pub mod screenshot;
pub mod stream;
pub mod view;
pub mod window;

pub use voxel_reference::{deferred_reference, reference_raycast};
