//! The MagicaVoxel loader on the real sample models: every voxel of every placed model lands in
//! the world exactly once, with its colour index as block id.

use tests::sample_vox_files;
use viewer::scene::vox::load_vox_file;
use voxel_core::storage::VoxelStorage;
use voxel_core::{BlockId, ChunkSize};

#[test]
fn every_sample_model_loads_and_keeps_every_voxel() {
    let files = sample_vox_files();
    for path in &files {
        let scene = load_vox_file(path, ChunkSize::S32, 1 << 24)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let data = dot_vox::load(path.to_str().unwrap()).unwrap();
        assert!(scene.voxel_count > 0, "{}: no voxels", path.display());

        // The world holds exactly as many non-air voxels as were written, unless two placed
        // models overlap (they do not in these files), and each id is a colour index 1..=255.
        let stored: usize = scene.world.iter().map(|(_, c)| c.non_air_count()).sum();
        assert_eq!(
            stored,
            scene.voxel_count,
            "{}: voxels lost or overlapping",
            path.display()
        );
        let (lo, hi) = scene.bounds.unwrap();
        let used: std::collections::HashSet<u8> = data
            .models
            .iter()
            .flat_map(|m| m.voxels.iter().map(|v| v.i))
            .collect();
        for (coord, chunk) in scene.world.iter() {
            for (local, id) in chunk.iter() {
                if id == BlockId::AIR {
                    continue;
                }
                let p = coord.world_pos(local, ChunkSize::S32).unwrap();
                assert!(
                    lo.x <= p.x
                        && p.x <= hi.x
                        && lo.y <= p.y
                        && p.y <= hi.y
                        && lo.z <= p.z
                        && p.z <= hi.z
                );
                assert!(
                    (1..=255).contains(&id.0) && used.contains(&((id.0 - 1) as u8)),
                    "{}: id {}",
                    path.display(),
                    id.0
                );
            }
        }
        // A file with no scene graph shows model 0; one with a graph shows at least one model.
        if data.scenes.is_empty() {
            assert_eq!(scene.voxel_count, data.models[0].voxels.len());
        }
        eprintln!(
            "{}: {} voxels, bounds {:?}..{:?}",
            path.file_name().unwrap().to_string_lossy(),
            scene.voxel_count,
            lo,
            hi
        );
    }
}

#[test]
fn a_scene_over_the_voxel_limit_is_refused_with_the_limit_named() {
    let Some(path) = sample_vox_files().into_iter().next() else {
        return;
    };
    let err =
        load_vox_file(&path, ChunkSize::S32, 10).expect_err("10 voxels is too few for any sample");
    assert!(err.to_string().contains("10 voxels"), "{err}");
}

#[test]
fn truncated_sample_files_are_errors_not_panics() {
    for path in sample_vox_files() {
        let bytes = std::fs::read(&path).unwrap();
        for cut in [8, bytes.len() / 3, bytes.len() / 2, bytes.len() - 1] {
            // Either a clean error or (if the cut lands on a chunk boundary) a smaller scene.
            let _ = viewer::scene::vox::load_vox_bytes(&bytes[..cut], ChunkSize::S32, 1 << 24);
        }
    }
}
