//! In every blocky mode, the exported mesh is exact: its signed volume equals the voxel count
//! and its area the count of visible voxel faces (times the output scale), on every sample
//! model, on scenes with transforms, hidden nodes and every material kind, and on the
//! terrain. Greedy meshes have T-junctions, so volume and area are the test, not
//! edge-watertightness. Every triangle also faces the way its normal says.

mod support;

use std::path::Path;

use support::{ReadPrimitive, Voxels, area, read_glb, read_obj, s, signed_volume, voxmesh_ok};
use voxel_core::ChunkSize;
use voxel_scene::vox::load_vox_file;

/// Relative error allowed for scales that `f32` cannot hold exactly (a few `f32` steps).
const TOLERANCE: f64 = 1e-6;

/// Checks one mesh against the voxels it was made from: the opaque primitives enclose the
/// opaque voxels, all primitives together cover the visible faces, and triangles face their
/// normals. Returns the volume of the see-through primitives.
///
/// Positions are `f32`, exact for voxel corners times a power of two; other scales (0.1) put
/// each coordinate within half an `f32` step, so the check allows `TOLERANCE` relative error.
fn check(
    what: &str,
    primitives: &[ReadPrimitive],
    voxels: &Voxels,
    cell: f64,
    normals: bool,
) -> f64 {
    let exact = cell.log2().fract() == 0.0;
    let tolerance = if exact { 0.0 } else { TOLERANCE };
    let opaque: Vec<&ReadPrimitive> = primitives.iter().filter(|p| !p.blend).collect();
    let blend: Vec<&ReadPrimitive> = primitives.iter().filter(|p| p.blend).collect();
    let all: Vec<&ReadPrimitive> = primitives.iter().collect();
    let opaque_voxels = (voxels.count() - voxels.transparent_count()) as f64;
    let volume = signed_volume(&opaque);
    let want_volume = opaque_voxels * cell.powi(3);
    assert!(
        (volume - want_volume).abs() <= tolerance * want_volume,
        "{what}: opaque volume {volume}, voxels give {want_volume}"
    );
    let faces = area(&all);
    let want_faces = voxels.visible_faces() as f64 * cell * cell;
    assert!(
        (faces - want_faces).abs() <= tolerance * want_faces,
        "{what}: area {faces}, visible faces give {want_faces}"
    );
    if normals {
        for p in primitives {
            for t in &p.triangles {
                let [a, b, c] = t.map(|i| p.positions[i as usize]);
                let n = p.normals[t[0] as usize];
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                let cross = [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ];
                let dot: f64 = (0..3).map(|i| cross[i] * f64::from(n[i])).sum();
                assert!(dot > 0.0, "{what}: a triangle faces against its normal");
            }
        }
    }
    signed_volume(&blend)
}

fn vox_voxels(path: &Path, size: ChunkSize, hidden: bool) -> Voxels {
    let options = voxel_scene::vox::VoxOptions {
        include_hidden: hidden,
        ..voxel_scene::vox::VoxOptions::new(size, 1 << 26)
    };
    let scene = voxel_scene::vox::load_vox_file_with(path, &options).expect("loads");
    Voxels::of(&scene.world, &scene.palette)
}

#[test]
fn every_sample_in_every_blocky_mode_encloses_its_voxels() {
    let dir = support::temp_dir();
    for path in support::samples::sample_vox_files() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let voxels = vox_voxels(&path, ChunkSize::S32, false);
        let runs: [&[&str]; 5] = [
            &["--mode", "faces"],
            &["--mode", "greedy"],
            &["--mode", "greedy", "--ao"],
            &["--mode", "greedy", "--chunk", "16"],
            &["--mode", "faces", "--chunk", "62", "--ao", "--threads", "1"],
        ];
        for extra in runs {
            let out = dir.path().join(format!("{name}.glb"));
            let mut args = vec![s(&path), "-o", s(&out)];
            args.extend_from_slice(extra);
            voxmesh_ok(&args);
            let what = format!("{name} {extra:?}");
            check(&what, &read_glb(&out), &voxels, 1.0, true);
        }
    }
}

#[test]
fn scale_multiplies_volume_by_its_cube_and_area_by_its_square() {
    let dir = support::temp_dir();
    let Some(path) = support::samples::sample_vox_files().into_iter().next() else {
        return;
    };
    let voxels = vox_voxels(&path, ChunkSize::S32, false);
    for scale in ["0.5", "4", "0.1", "3"] {
        let out = dir.path().join("scaled.glb");
        voxmesh_ok(&[s(&path), "-o", s(&out), "--scale", scale]);
        check(
            &format!("scale {scale}"),
            &read_glb(&out),
            &voxels,
            scale.parse().unwrap(),
            true,
        );
    }
}

#[test]
fn lod_meshes_enclose_the_downsampled_voxels() {
    let dir = support::temp_dir();
    for path in support::samples::sample_vox_files() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let scene = load_vox_file(&path, ChunkSize::S16, 1 << 26).unwrap();
        let classes = mesher::BlockClasses::from_palette(&scene.palette);
        for lod in [1u32, 2] {
            let coarse = voxmesh::mesh::downsample(scene.world.clone(), &classes, lod).unwrap();
            let voxels = Voxels::of(&coarse, &scene.palette);
            let out = dir.path().join("lod.glb");
            let lod_arg = lod.to_string();
            voxmesh_ok(&[s(&path), "-o", s(&out), "--lod", &lod_arg, "--chunk", "16"]);
            let cell = f64::from(1u32 << lod);
            check(
                &format!("{name} lod {lod}"),
                &read_glb(&out),
                &voxels,
                cell,
                true,
            );
        }
    }
}

#[test]
fn scenes_with_transforms_hidden_nodes_and_materials_are_exact() {
    let dir = support::temp_dir();
    let path = support::write_vox(dir.path(), "materials.vox", &support::material_scene());
    for hidden in [false, true] {
        let voxels = vox_voxels(&path, ChunkSize::S32, hidden);
        for mode in ["faces", "greedy"] {
            let out = dir.path().join("m.glb");
            let mut args = vec![s(&path), "-o", s(&out), "--mode", mode];
            if hidden {
                args.push("--hidden");
            }
            voxmesh_ok(&args);
            let what = format!("materials {mode} hidden {hidden}");
            let glass_volume = check(&what, &read_glb(&out), &voxels, 1.0, true);
            // The glass block touches nothing opaque, so it is closed too.
            assert_eq!(glass_volume, voxels.transparent_count() as f64, "{what}");
            assert_eq!(voxels.transparent_count(), 8);
        }
    }
    // The hidden model is left out: one voxel fewer than with --hidden.
    assert_eq!(
        vox_voxels(&path, ChunkSize::S32, true).count(),
        vox_voxels(&path, ChunkSize::S32, false).count() + 1
    );
}

#[test]
fn obj_output_is_exact_too() {
    let dir = support::temp_dir();
    let path = support::write_vox(dir.path(), "materials.vox", &support::material_scene());
    let voxels = vox_voxels(&path, ChunkSize::S32, false);
    let out = dir.path().join("m.obj");
    voxmesh_ok(&[s(&path), "-o", s(&out)]);
    // The OBJ reader does not tell see-through groups apart: check the total area and the
    // volume of everything (the glass is closed on its own).
    let groups = read_obj(&out);
    let all: Vec<&ReadPrimitive> = groups.iter().collect();
    assert_eq!(area(&all), voxels.visible_faces() as f64);
    assert_eq!(signed_volume(&all), voxels.count() as f64);
    assert!(dir.path().join("m.mtl").is_file());
}

#[test]
fn terrain_with_water_is_exact_in_every_blocky_mode() {
    let dir = support::temp_dir();
    for chunk in [ChunkSize::S16, ChunkSize::S62] {
        let terrain = voxel_scene::terrain_columns(11, chunk, 70);
        let voxels = Voxels::of(&terrain.world, &terrain.palette);
        assert!(voxels.transparent_count() > 0, "the patch has water");
        for mode in ["faces", "greedy"] {
            let out = dir.path().join("t.glb");
            let edge = chunk.edge().to_string();
            voxmesh_ok(&[
                "terrain:11:70",
                "-o",
                s(&out),
                "--mode",
                mode,
                "--chunk",
                &edge,
                "--ao",
            ]);
            check(
                &format!("terrain {mode} {edge}"),
                &read_glb(&out),
                &voxels,
                1.0,
                true,
            );
        }
    }
}
