//! # voxel-reference
//!
//! CPU reference renderers, slow and simple on purpose: the ground truth the GPU renderer's
//! images are tested against, and what the viewer draws without a GPU.
//!
//! - [`reference_raycast`]: one ray per pixel, marched voxel by voxel;
//! - [`deferred_reference`]: those rays shaded with the GPU's lighting model (the one CPU renderer).
//! - [`prop_raster`]: glTF props (`voxel_scene::props`) rasterised with the same lighting,
//!   placed by the prop pass's camera-relative rule.
//! - [`grass_raster`]: clutter units as the grass pass's crossed quads, rasterised with the
//!   same lighting.
//!
//! All take the stack's one camera and lighting ([`render_model::Camera`],
//! [`render_model::Lighting`]). A crate of its own, without wgpu, so that the image tests and
//! the benchmarks' reports use the references without building a GPU backend or the viewer's
//! window (winit, egui).

pub mod deferred_reference;
pub mod grass_raster;
pub mod prop_raster;
pub mod reference_raycast;
