//! # viewer
//!
//! Shows voxel scenes: the built-in procedural terrain (and, in later stages, MagicaVoxel models
//! and glTF props), in a window ([`window`]) or, without a display, to a PNG file.
//!
//! The renderer today is [`reference_raycast`], the CPU ground truth that GPU images are tested
//! against.

pub mod deferred_reference;
pub mod gpu_view;
pub mod reference_raycast;
pub mod scene;
pub mod window;
