//! # voxel-reference
//!
//! CPU reference renderers, slow and simple on purpose: the ground truth the GPU renderer's
//! images are tested against, and what the viewer draws without a GPU.
//!
//! - [`reference_raycast`]: one ray per pixel, marched voxel by voxel, shaded simply;
//! - [`deferred_reference`]: the same rays shaded with the GPU's deferred lighting model;
//! - [`camera`] and [`lighting`]: the pinhole camera and the light and sky both renderers (and
//!   the viewer's GPU path, through [`lighting::lighting_params`]) use.
//!
//! A crate of its own so that the image tests and the benchmarks' reports use the references
//! without building the viewer's window (winit, egui).

pub mod camera;
pub mod deferred_reference;
pub mod lighting;
pub mod reference_raycast;
