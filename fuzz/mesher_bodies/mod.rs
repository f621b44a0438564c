//! The bodies of the fuzz targets for the far-field and LOD stages of the mesher, one
//! `pub fn <target>(data: &[u8])` per target: `vertical_shells`, `heightmap_boxes`,
//! `surface_blocks`, `place_clutter` and `lod`.
//!
//! Like `fuzz/bodies.rs`, this folder is compiled twice: by each of these fuzz targets
//! (`fuzz/fuzz_targets/<target>.rs`, as `#[path = "../mesher_bodies/mod.rs"] mod
//! mesher_bodies;`) and by the corpus replay test (`tests/tests/fuzz_corpus_replay.rs`), so
//! `cargo test` replays every committed corpus input through the code that fuzzing ran.
//!
//! Every body decodes an arbitrary padded chunk and palette ([`input::ChunkInput`]: every chunk
//! size, every material class, up to 15 transparent ids, unknown ids up to 65,535) and checks
//! the stage against a plain per-voxel reference of its documented rules, not just that it
//! does not panic (details in each body's docs).
#![allow(dead_code, unused_imports)] // Each fuzz target uses one body; the replay test uses them all.

#[path = "input.rs"]
pub(crate) mod input;

#[path = "clutter.rs"]
mod clutter;
#[path = "heightmap.rs"]
mod heightmap;
#[path = "lod.rs"]
mod lod;
#[path = "shells.rs"]
mod shells;
#[path = "surface_blocks.rs"]
mod surface_blocks;

pub(crate) use clutter::place_clutter;
pub(crate) use heightmap::heightmap_boxes;
pub(crate) use lod::lod;
pub(crate) use shells::vertical_shells;
pub(crate) use surface_blocks::surface_blocks;

use mesher::BlockClasses;
use voxel_core::{BlockId, PaddedChunk};

/// The exposed faces of the chunk voxel at padded position `pos` (`FaceDirection::ALL` order),
/// by the exposure rules in the docs of `mesher::surface_blocks`, written voxel by voxel: a
/// neighbour *hides* a face when it is neither air nor transparent (unknown ids hide); the face
/// of voxel `v` towards `n` is exposed when `v` is not air, `n` does not hide, and `v` is not a
/// transparent voxel of the same id as `n`.
pub(crate) fn exposed_faces(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    pos: [u32; 3],
) -> [bool; 6] {
    let voxels = padded.voxels();
    let p = padded.padded_edge();
    let [x, y, z] = pos.map(|a| a as usize);
    let at = |x: usize, y: usize, z: usize| voxels[x + p * (y + p * z)];
    let id = at(x, y, z);
    let neighbours = [
        at(x + 1, y, z),
        at(x - 1, y, z),
        at(x, y + 1, z),
        at(x, y - 1, z),
        at(x, y, z + 1),
        at(x, y, z - 1),
    ];
    neighbours.map(|neighbour| {
        let hides = !neighbour.is_air() && !classes.is_transparent(neighbour);
        let same_transparent = classes.is_transparent(id) && neighbour == id;
        !id.is_air() && !hides && !same_transparent
    })
}

/// The padded voxel at `pos` (inside the padded chunk).
pub(crate) fn id_at(padded: &PaddedChunk, pos: [u32; 3]) -> BlockId {
    let p = padded.padded_edge();
    let [x, y, z] = pos.map(|a| a as usize);
    padded.voxels()[x + p * (y + p * z)]
}

/// True when `id` is neither air nor in the palette.
pub(crate) fn unknown(classes: &BlockClasses, id: BlockId) -> bool {
    !id.is_air() && classes.class(id).is_none()
}

/// Every padded position of the chunk's own voxels (`1..=edge` per axis), z slowest, x fastest.
pub(crate) fn chunk_positions(padded: &PaddedChunk) -> impl Iterator<Item = [u32; 3]> {
    // Half-open ranges: an inclusive range checks for its end on every step.
    let end = padded.size().edge() + 1;
    (1..end).flat_map(move |z| (1..end).flat_map(move |y| (1..end).map(move |x| [x, y, z])))
}
