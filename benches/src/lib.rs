//! # benches
//!
//! Criterion benchmarks of every stage of the stack (`cargo bench -p benches`), and the
//! deterministic inputs they share. Results that matter are copied into `BENCHMARKS.md` with
//! the command that produced them and the machine they ran on.
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`cpu_time`] | [`ThreadCpuTime`](cpu_time::ThreadCpuTime), the criterion clock the bench targets use by default (`BENCH_CLOCK=wall` for wall time) |
//! | [`gpu_bench`] | the GPU benchmark (binary `gpu_bench`): terrain scenes of growing chunk counts drawn by the renderer, GPU time per pass, bytes, CPU frame time |
//! | [`gpu_scene`] | the GPU benchmark's scene: the viewer's terrain over `side x side` columns, meshed, nearest chunks first |
//! | [`rng`] | a tiny seeded PRNG (`voxel_scene::rng`), so every input is the same on every machine and every run |
//! | [`inputs::chunks`] | terrain chunks with caves (32^3, 62^3), a world of 27 of them, uniform and random chunks, random positions |
//! | [`inputs::formats`] | arrays of valid field values for each packed GPU format, and unit normals |
//! | [`smooth_inputs`] | density grids for SurfaceNets (the `fast-surface-nets` sphere and sine at 34^3, a 62^3 terrain) and the NoCubes terrain chunk |
//! | [`report`] | the speed-against-accuracy report (binary `tradeoff_report`, writes `docs/tradeoff.md`): CPU meshing per mode and chunk size, smooth-mesh and format error, the GPU budget sweep, renders at 2^30 offsets |
//! | [`mesh_inputs`] | padded chunks and palettes for the blocky meshers and their peers, at any chunk size: spheres, terrain, checkerboard, random fill, full, empty, Menger sponges, a foliage scene, the `.vox` samples cut into chunks |
//!
//! The bench targets live in `benches/benches/` (one file per crate: `voxel_core.rs` today).
//! Every input is built once, outside the timed loop, by a function here, so two benches that
//! say "terrain 32^3" measure the same voxels.
//!
//! ```
//! use benches::inputs::chunks::{terrain_chunk, TERRAIN_CENTRE};
//! use voxel_core::ChunkSize;
//! use voxel_core::storage::VoxelStorage;
//!
//! let a = terrain_chunk(ChunkSize::S16, TERRAIN_CENTRE);
//! let b = terrain_chunk(ChunkSize::S16, TERRAIN_CENTRE);
//! assert_eq!(a, b); // deterministic
//! assert!(a.non_air_count() > 0);
//! ```

pub mod cpu_time;
pub mod gpu_bench;
pub mod gpu_scene;
pub mod inputs;
pub mod mesh_inputs;
pub mod report;
pub use voxel_scene::rng;
pub mod smooth_inputs;
