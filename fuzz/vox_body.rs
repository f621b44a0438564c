//! The body of the `vox_loader` fuzz target: the MagicaVoxel loader of `voxel-scene` on
//! arbitrary bytes.
//!
//! Compiled twice, like `bodies.rs`: by the target (`fuzz_targets/vox_loader.rs`) and by the
//! corpus replay test (`tests/tests/fuzz_corpus_replay.rs`). It checks properties, not just
//! "does not panic":
//!
//! - an error names a real place: a chunk it names starts at that offset with that id, a
//!   truncation's offset lies inside the file, and its message is not empty;
//! - a loaded scene is consistent: the voxel count is what the world stores, the bounds are
//!   the exact bounds of the stored voxels, every id is a colour index 1..=255, 256 materials
//!   with values in their documented ranges, and the report's counts agree with each other;
//! - the chunk size changes only how voxels are stored: 16^3 and 32^3 give the same voxels;
//! - without hidden nodes, `include_hidden` changes nothing.

use voxel_core::ChunkSize;
use voxel_core::storage::VoxelStorage;
use voxel_scene::vox::{VoxError, VoxOptions, VoxScene, load_vox_with};

/// Voxels a fuzzed scene may place (keeps each run fast; the limit itself is checked).
const MAX_VOXELS: usize = 1 << 16;

/// Every stored voxel as `(x, y, z, id)`, sorted.
fn voxels(scene: &VoxScene) -> Vec<(i32, i32, i32, u16)> {
    let size = scene.world.size();
    let mut out: Vec<(i32, i32, i32, u16)> = scene
        .world
        .iter()
        .flat_map(|(coord, chunk)| {
            chunk
                .iter()
                .filter(|(_, id)| !id.is_air())
                .map(move |(local, id)| {
                    let p = coord
                        .world_pos(local, size)
                        .expect("stored voxels are in the world");
                    (p.x, p.y, p.z, id.0)
                })
        })
        .collect();
    out.sort_unstable();
    out
}

fn check_error(data: &[u8], error: &VoxError) {
    assert!(!error.to_string().is_empty());
    if let Some(at) = error.chunk() {
        assert!(
            data.get(at.offset..at.offset + 4) == Some(&at.id.0[..]),
            "{error}: no chunk {} at byte {}",
            at.id,
            at.offset
        );
    }
    if let VoxError::Truncated {
        offset, available, ..
    } = error
    {
        assert!(*offset <= data.len(), "{error}");
        assert!(offset + available <= data.len(), "{error}");
    }
}

fn check_scene(scene: &VoxScene) -> Vec<(i32, i32, i32, u16)> {
    let all = voxels(scene);
    assert_eq!(all.len(), scene.voxel_count);
    match scene.bounds {
        None => assert!(all.is_empty()),
        Some((lo, hi)) => {
            let axis = |f: fn(&(i32, i32, i32, u16)) -> i32| {
                (all.iter().map(f).min(), all.iter().map(f).max())
            };
            // An overlap replaces an id but never empties a position, so the bounds of every
            // voxel written are the bounds of the stored ones.
            assert_eq!(
                (axis(|v| v.0), axis(|v| v.1), axis(|v| v.2)),
                (
                    (Some(lo.x), Some(hi.x)),
                    (Some(lo.y), Some(hi.y)),
                    (Some(lo.z), Some(hi.z)),
                )
            );
        }
    }
    assert!(all.iter().all(|v| (1..=255).contains(&v.3)));
    assert_eq!(scene.materials.len(), 256);
    assert_eq!(scene.palette.len(), 256);
    for m in &scene.materials {
        for v in [m.metalness, m.roughness, m.transparency] {
            assert!((0.0..=1.0).contains(&v), "{m:?}");
        }
        assert!(m.emission.is_finite() && m.emission >= 0.0, "{m:?}");
    }
    let r = &scene.report;
    assert!(r.models >= 1 && r.models_drawn <= r.models);
    assert!(r.hidden_by_layer <= r.hidden_nodes);
    all
}

/// The `vox_loader` target: see the module docs.
pub(crate) fn vox_loader(data: &[u8]) {
    let options = VoxOptions::new(ChunkSize::S16, MAX_VOXELS);
    let scene = match load_vox_with(data, &options) {
        Ok(scene) => scene,
        Err(error) => {
            check_error(data, &error);
            if let VoxError::TooManyVoxels { limit } = error {
                assert_eq!(limit, MAX_VOXELS);
            }
            return;
        }
    };
    let all = check_scene(&scene);
    let wide = load_vox_with(data, &VoxOptions::new(ChunkSize::S32, MAX_VOXELS))
        .expect("the chunk size cannot make a file invalid");
    assert_eq!(
        voxels(&wide),
        all,
        "16^3 and 32^3 chunks hold different voxels"
    );
    if scene.report.hidden_nodes == 0 {
        let with_hidden = VoxOptions {
            include_hidden: true,
            ..options
        };
        let again = load_vox_with(data, &with_hidden).expect("nothing hidden to add");
        assert_eq!(voxels(&again), all);
    }
}
