//! Examples of the workspace's libraries used from outside, each under 80 lines and run by
//! the test command (`scripts/test-all.sh`):
//!
//! - `vox_to_quads.rs`: the mesher alone, a MagicaVoxel `.vox` file to packed quads
//!   (`cargo run -p examples --example vox_to_quads -- model.vox [out.bin]`);
//! - `host_wgpu.rs`: the wgpu backend in a host's own wgpu setup (its instance, adapter,
//!   device, queue, colour and depth targets), drawing the host's own `PackedQuad`s
//!   (`cargo run -p examples --example host_wgpu`).
