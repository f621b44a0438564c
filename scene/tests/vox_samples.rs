//! The loader on the real MagicaVoxel sample models, cross-checked against the `dot_vox`
//! crate: the same voxels (model 0 of these files, which have no scene graph), the same
//! colours, and the frames of the animated ones reported.

#[path = "support/samples.rs"]
mod samples;

use std::collections::BTreeMap;

use voxel_core::storage::VoxelStorage;
use voxel_core::{ChunkSize, MaterialClass};
use voxel_scene::vox::{VoxMaterialKind, load_vox_bytes, load_vox_file};

/// The samples' material chunks, counted in the raw bytes: T-Rex and deer carry a `MATT`
/// (the pre-0.99 material chunk) for each of 255 colour indices, all of type 0 (diffuse,
/// weight 1); no sample carries `MATL`. The loader reads each as diffuse, and the renderer's
/// material of a diffuse index is fully rough and not metal, so these models are drawn
/// Lambertian, exactly as before materials were honoured.
#[test]
fn sample_material_chunks_load_as_diffuse_and_draw_lambertian() {
    let files = samples::sample_vox_files();
    let mut with_materials = 0;
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy();
        let bytes = std::fs::read(path).unwrap();
        let count = |id: &[u8; 4]| bytes.windows(4).filter(|w| *w == id).count();
        let (matt, matl) = (count(b"MATT"), count(b"MATL"));
        if matt + matl == 0 {
            continue;
        }
        with_materials += 1;
        assert_eq!((matt, matl), (255, 0), "{name}");
        let scene = load_vox_file(path, ChunkSize::S32, 1 << 24).unwrap();
        for (index, m) in scene.materials.iter().enumerate().skip(1) {
            assert_eq!(m.kind, VoxMaterialKind::Diffuse, "{name}: index {index}");
            let r = m.to_material();
            assert_eq!(
                (r.roughness, r.metalness, r.emission, r.volume, r.class),
                (255, 0, 0, false, MaterialClass::Opaque),
                "{name}: index {index}"
            );
        }
    }
    assert!(
        files.is_empty() || with_materials >= 2,
        "T-Rex and deer carry material chunks"
    );
}

#[test]
fn every_sample_loads_and_matches_dot_vox() {
    let files = samples::sample_vox_files();
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy();
        let scene =
            load_vox_file(path, ChunkSize::S32, 1 << 24).unwrap_or_else(|e| panic!("{name}: {e}"));
        let data = dot_vox::load(path.to_str().unwrap()).unwrap();
        assert!(
            data.scenes.is_empty(),
            "{name}: the samples have no scene graph"
        );

        // Model 0, with its corner at the origin, z up to y up, id = file colour index.
        let mut want = BTreeMap::new();
        for v in &data.models[0].voxels {
            let id = u16::from(v.i) + 1;
            want.insert([i32::from(v.x), i32::from(v.z), -1 - i32::from(v.y)], id);
        }
        let mut got = BTreeMap::new();
        for (coord, chunk) in scene.world.iter() {
            for (local, id) in chunk.iter() {
                if !id.is_air() {
                    let p = coord.world_pos(local, ChunkSize::S32).unwrap();
                    got.insert([p.x, p.y, p.z], id.0);
                }
            }
        }
        assert_eq!(got, want, "{name}: voxels differ from dot_vox's model 0");
        assert_eq!(scene.voxel_count, want.len());
        for (index, colour) in data.palette.iter().enumerate().take(255) {
            assert_eq!(
                scene.materials[index + 1].colour,
                <[u8; 4]>::from(colour),
                "{name}: colour index {}",
                index + 1
            );
        }
        assert_eq!(scene.report.models, data.models.len());
        assert_eq!(scene.report.animated, data.models.len() > 1, "{name}");
        eprintln!(
            "{name}: {} voxels, {} models, notes {:?}",
            scene.voxel_count,
            data.models.len(),
            scene.report.notes()
        );
    }
}

#[test]
fn every_cut_of_a_sample_is_refused_without_panicking() {
    for path in samples::sample_vox_files() {
        let bytes = std::fs::read(&path).unwrap();
        // Every cut of the small files; a spread of cuts of the large ones.
        let step = (bytes.len() / 4000).max(1);
        for cut in (0..bytes.len()).step_by(step) {
            let result = load_vox_bytes(&bytes[..cut], ChunkSize::S16, 1 << 24);
            assert!(result.is_err(), "{}: cut at {cut} accepted", path.display());
        }
    }
}
