//! # mesher
//!
//! Surface extraction for voxel chunks. Every mesher reads a [`PaddedChunk`] (a chunk plus its
//! one-voxel border, gathered by `voxel_core::gather_neighbourhood`) and writes packed GPU
//! formats from `voxel_core::formats` into a reusable output buffer that keeps its capacity.
//!
//! `no_std` + `alloc`; feature `parallel` adds rayon batch meshing, feature `std` the
//! `std::error::Error` impls and run-time CPU detection: the blocky mesher is compiled twice,
//! for the build's target and for x86-64 with AVX2 and BMI2, and runs the best copy the CPU
//! supports ([`InstructionSet`]); both give the same quads.
//!
//! [`PaddedChunk`]: voxel_core::PaddedChunk
#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod batch;
pub mod blocky;
mod classes;
pub mod clutter;
mod error;
pub mod heightmap;
mod instruction_set;
pub mod lod;
mod quad_layer;
pub mod shells;
pub mod smooth;
pub mod surface_blocks;

#[cfg(feature = "parallel")]
pub use batch::mesh_chunks;
pub use batch::{ChunkMesh, ChunkMesher, MeshSettings, SurfaceMode, mesh_chunks_sequential};
pub use classes::BlockClasses;
pub use clutter::{
    ClutterLayer, ClutterParams, InvalidClutterDensity, clutter_extent, clutter_hash, place_clutter,
};
pub use error::MeshError;
pub use instruction_set::InstructionSet;
pub use quad_layer::QuadLayer;
pub use shells::{ShellRun, ShellRuns, vertical_shells};
pub use surface_blocks::{SUB_BLOCK_EDGE, SubBlockRange, SurfaceBlocks, surface_blocks};
