//! Every kind of malformed `.vox` file is refused with an error that names what is wrong and
//! where; none panics. The files are built by the test writer, each breaking one rule of a
//! valid file.

#[path = "support/writer.rs"]
mod writer;

use voxel_core::ChunkSize;
use voxel_scene::vox::{VoxError, load_vox_bytes};
use writer::{VoxWriter, two_model_scene};

fn load(bytes: &[u8]) -> Result<voxel_scene::vox::VoxScene, VoxError> {
    load_vox_bytes(bytes, ChunkSize::S16, 1 << 20)
}

/// Loads `bytes`, expects an error, and checks that its message holds every piece of `parts`.
fn refused(bytes: &[u8], parts: &[&str]) -> VoxError {
    let err = match load(bytes) {
        Ok(_) => panic!("accepted; expected an error naming {parts:?}"),
        Err(e) => e,
    };
    let message = err.to_string();
    for part in parts {
        assert!(
            message.contains(part),
            "message {message:?} does not name {part:?}"
        );
    }
    err
}

#[test]
fn the_valid_base_scene_loads() {
    let scene = load(&two_model_scene().bytes()).expect("valid");
    assert_eq!(scene.voxel_count, 7);
}

#[test]
fn every_truncation_names_the_chunk_and_the_offset() {
    let w = two_model_scene();
    let bytes = w.bytes();
    // Chunk extents: (header offset, end) of each child of MAIN.
    let extents: Vec<(usize, usize)> = (0..w.len())
        .map(|i| {
            let end = if i + 1 < w.len() {
                w.offset_of(i + 1)
            } else {
                bytes.len()
            };
            (w.offset_of(i), end)
        })
        .collect();
    for cut in 0..bytes.len() {
        let err = load(&bytes[..cut])
            .err()
            .unwrap_or_else(|| panic!("a file cut at byte {cut} of {} was accepted", bytes.len()));
        let message = err.to_string();
        match cut {
            0..4 => assert!(matches!(err, VoxError::NotVox { .. }), "{cut}: {err}"),
            4..20 => assert!(
                matches!(err, VoxError::Truncated { chunk: None, .. }),
                "{cut}: {err}"
            ),
            _ => {
                let &(start, _) = extents
                    .iter()
                    .find(|(s, e)| (*s..*e).contains(&cut))
                    .expect("every cut after the MAIN header is inside a child");
                let VoxError::Truncated { chunk, offset, .. } = err else {
                    panic!("cut at {cut}: expected truncation, got {err}");
                };
                if cut == start {
                    // Cut between chunks: 'MAIN' promises more.
                    let main = chunk.expect("MAIN is named");
                    assert_eq!((main.offset, offset), (8, cut), "{message}");
                    assert!(message.contains("'MAIN' at byte 8"), "{message}");
                } else if cut < start + 12 {
                    // Cut inside the chunk's header.
                    assert_eq!((chunk, offset), (None, start), "cut at {cut}: {message}");
                } else {
                    let chunk = chunk.expect("the chunk is named");
                    assert_eq!(chunk.offset, start, "cut at {cut}: {message}");
                    assert!(message.contains(&format!("at byte {start}")), "{message}");
                    assert!(message.contains(&chunk.id.to_string()), "{message}");
                }
            }
        }
    }
}

#[test]
fn a_main_chunk_longer_than_the_file_is_truncation_of_main() {
    let mut bytes = two_model_scene().bytes();
    let children = u32::from_le_bytes(bytes[16..20].try_into().unwrap());
    bytes[16..20].copy_from_slice(&(children + 100).to_le_bytes());
    refused(
        &bytes,
        &["'MAIN' at byte 8 is truncated", "100 bytes needed"],
    );
}

#[test]
fn a_chunk_longer_than_main_is_truncated() {
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]]);
    let mut bytes = w.bytes();
    // The XYZI chunk (second child) claims 4 more bytes than MAIN holds.
    let at = w.offset_of(1);
    bytes[at + 4..at + 8].copy_from_slice(&12u32.to_le_bytes());
    refused(&bytes, &["'XYZI' at byte 44 is truncated"]);
    assert_eq!(at, 44);
}

#[test]
fn voxels_outside_their_model_are_refused_with_model_and_position() {
    for (voxel, position) in [([2, 0, 0, 1], "(2, 0, 0)"), ([0, 0, 3, 1], "(0, 0, 3)")] {
        let mut w = VoxWriter::new();
        w.model([1, 1, 1], &[[0, 0, 0, 1]])
            .model([2, 2, 3], &[[1, 1, 1, 2], voxel]);
        let err = refused(&w.bytes(), &["model 1", "voxel 1", position, "2 x 2 x 3"]);
        assert!(matches!(err, VoxError::VoxelOutsideModel { model: 1, .. }));
    }
}

#[test]
fn model_sizes_of_zero_negative_or_huge_are_refused() {
    for size in [
        [0, 1, 1],
        [1, -1, 1],
        [1, 1, 257],
        [i32::MAX, 1, 1],
        [i32::MIN, 0, 0],
    ] {
        let mut w = VoxWriter::new();
        w.model(size, &[]);
        let shown = format!("{} x {} x {}", size[0], size[1], size[2]);
        let err = refused(&w.bytes(), &["model 0", &shown, "'SIZE' at byte 20"]);
        assert!(
            matches!(err, VoxError::BadModelSize { model: 0, .. }),
            "{err}"
        );
    }
}

#[test]
fn voxel_counts_that_lie_are_refused() {
    for declared in [0u32, 1, 3, 1000, u32::MAX] {
        let mut w = VoxWriter::new();
        w.model([4, 4, 4], &[[0, 0, 0, 1], [1, 0, 0, 1]]);
        let mut bytes = w.bytes();
        let at = w.offset_of(1) + 12;
        bytes[at..at + 4].copy_from_slice(&declared.to_le_bytes());
        let err = refused(
            &bytes,
            &[
                "model 0",
                &format!("{declared} voxels"),
                "has 8 bytes",
                "'XYZI' at byte 44",
            ],
        );
        assert!(matches!(err, VoxError::VoxelCountMismatch { .. }), "{err}");
    }
    // Voxel bytes that are not a whole number of voxels.
    let mut w = VoxWriter::new();
    w.chunk(
        b"SIZE",
        [1i32, 1, 1].iter().flat_map(|v| v.to_le_bytes()).collect(),
    )
    .chunk(b"XYZI", vec![1, 0, 0, 0, 0, 0, 0, 1, 9]);
    refused(
        &w.bytes(),
        &["model 0", "says it holds 1 voxels", "has 5 bytes"],
    );
}

#[test]
fn colour_index_zero_is_refused() {
    let mut w = VoxWriter::new();
    w.model([3, 3, 3], &[[0, 0, 0, 5], [1, 2, 0, 0]]);
    let err = refused(
        &w.bytes(),
        &["model 0", "voxel 1", "(1, 2, 0)", "colour index 0"],
    );
    assert!(matches!(err, VoxError::ColourIndexZero { .. }));
}

#[test]
fn files_without_a_model_are_refused() {
    refused(&VoxWriter::new().bytes(), &["no model"]);
    let mut w = VoxWriter::new();
    w.palette(&[[1, 2, 3, 255]; 256])
        .matl(1, &[("_type", "_glass")]);
    let err = refused(&w.bytes(), &["no model"]);
    assert!(matches!(err, VoxError::NoModels));
}

#[test]
fn framing_errors_are_refused() {
    refused(b"RIFF\x00\x00\x00\x00", &["not a MagicaVoxel file", "RIFF"]);
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]]);
    let valid = w.bytes();

    let mut not_main = valid.clone();
    not_main[8..12].copy_from_slice(b"MAIM");
    refused(
        &not_main,
        &["first chunk must be 'MAIN'", "'MAIM' at byte 8"],
    );

    let mut trailing = valid.clone();
    trailing.extend_from_slice(b"junk");
    refused(
        &trailing,
        &["4 bytes follow", &format!("byte {}", valid.len())],
    );

    let mut children = valid.clone();
    children[20 + 8..20 + 12].copy_from_slice(&1u32.to_le_bytes());
    refused(&children, &["'SIZE' at byte 20 has children"]);

    let mut odd_id = valid;
    odd_id[8..12].copy_from_slice(&[0, b'A', b'B', 0xff]);
    refused(&odd_id, &["'\\x00AB\\xff' at byte 8"]);
}

#[test]
fn chunks_of_the_wrong_length_are_refused() {
    let mut w = VoxWriter::new();
    w.chunk(b"SIZE", vec![1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0]);
    refused(
        &w.bytes(),
        &["'SIZE' at byte 20 holds 13 bytes", "12 bytes"],
    );

    // A palette of 256 or 255 colours loads (see `vox_scenes.rs`); any other length not.
    for wrong in [0, 4, 1016, 1021, 1028] {
        let mut w = VoxWriter::new();
        w.model([1, 1, 1], &[[0, 0, 0, 1]])
            .chunk(b"RGBA", vec![0; wrong]);
        refused(
            &w.bytes(),
            &["'RGBA'", &format!("holds {wrong} bytes"), "1024", "1020"],
        );
    }

    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .chunk(b"SIZE", vec![1, 0, 0, 0]);
    refused(&w.bytes(), &["'SIZE' at byte 64 is truncated"]);
}

#[test]
fn unpaired_model_chunks_and_lying_pack_counts_are_refused() {
    let size = |s: i32| {
        [s, s, s]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<u8>>()
    };
    let mut w = VoxWriter::new();
    w.chunk(b"SIZE", size(2)).chunk(b"RGBA", vec![0; 1024]);
    refused(&w.bytes(), &["'SIZE' at byte 20 is unpaired"]);

    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .chunk(b"XYZI", vec![0; 4]);
    refused(&w.bytes(), &["'XYZI' at byte 64 is unpaired"]);

    let mut w = VoxWriter::new();
    w.chunk(b"PACK", 2u32.to_le_bytes().to_vec())
        .model([1, 1, 1], &[[0, 0, 0, 1]]);
    let err = refused(&w.bytes(), &["'PACK' at byte 20", "2 models", "holds 1"]);
    assert!(matches!(err, VoxError::PackCountMismatch { .. }));
}

#[test]
fn scene_graph_errors_are_refused_with_the_node_named() {
    let base = |w: &mut VoxWriter| {
        w.model([1, 1, 1], &[[0, 0, 0, 1]]);
    };
    // Missing root.
    let mut w = VoxWriter::new();
    base(&mut w);
    w.transform(1, &[], 2, -1, &[]).shape(2, &[], &[0]);
    refused(&w.bytes(), &["no node 0"]);
    // A child that does not exist.
    let mut w = VoxWriter::new();
    base(&mut w);
    w.transform(0, &[], 7, -1, &[]);
    refused(
        &w.bytes(),
        &["scene node 0", "'nTRN' at byte 64", "child node 7"],
    );
    // A model that does not exist.
    let mut w = VoxWriter::new();
    base(&mut w);
    w.transform(0, &[], 1, -1, &[]).shape(1, &[], &[3]);
    refused(&w.bytes(), &["scene node 1", "'nSHP'", "model 3"]);
    // A cycle, and a node shared by two parents.
    let mut w = VoxWriter::new();
    base(&mut w);
    w.transform(0, &[], 1, -1, &[]).group(1, &[], &[0]);
    refused(&w.bytes(), &["scene node 0 is reached twice"]);
    let mut w = VoxWriter::new();
    base(&mut w);
    w.transform(0, &[], 1, -1, &[])
        .group(1, &[], &[2, 2])
        .transform(2, &[], 3, -1, &[])
        .shape(3, &[], &[0]);
    refused(&w.bytes(), &["scene node 2 is reached twice"]);
    // Two nodes with one id.
    let mut w = VoxWriter::new();
    base(&mut w);
    w.transform(0, &[], 1, -1, &[])
        .shape(1, &[], &[0])
        .shape(1, &[], &[0]);
    refused(&w.bytes(), &["defines scene node 1 a second time"]);
    // Too deep: a chain of transforms.
    let mut w = VoxWriter::new();
    base(&mut w);
    for id in 0..100 {
        w.transform(2 * id, &[], 2 * id + 1, -1, &[]);
        w.group(2 * id + 1, &[], &[2 * id + 2]);
    }
    w.shape(200, &[], &[0]);
    refused(&w.bytes(), &["deeper than 64"]);
    // A transform without frames.
    let mut w = VoxWriter::new();
    base(&mut w);
    w.transform_frames(0, &[], 1, -1, &[]).shape(1, &[], &[0]);
    refused(&w.bytes(), &["scene node 0", "frame count"]);
}

#[test]
fn bad_attribute_values_are_refused_with_key_and_value() {
    /// Node attributes, frame attributes, the key and the value the message must name.
    type Case<'a> = (
        &'a [(&'a str, &'a str)],
        &'a [(&'a str, &'a str)],
        &'a str,
        &'a str,
    );
    let cases: [Case<'_>; 6] = [
        (&[("_hidden", "yes")], &[], "_hidden", "\"yes\""),
        (&[], &[("_r", "3")], "_r", "\"3\""),
        (&[], &[("_r", "256")], "_r", "\"256\""),
        (&[], &[("_t", "1 2")], "_t", "\"1 2\""),
        (&[], &[("_t", "1 2 z")], "_t", "\"1 2 z\""),
        (&[], &[("_t", "1 2 3000000000")], "_t", "3000000000"),
    ];
    for (attributes, frame, key, value) in cases {
        let mut w = VoxWriter::new();
        w.model([1, 1, 1], &[[0, 0, 0, 1]])
            .transform(0, &[], 1, -1, &[])
            .group(1, &[], &[2])
            .transform(2, attributes, 3, -1, frame)
            .shape(3, &[], &[0]);
        refused(&w.bytes(), &["scene node 2", "'nTRN'", key, value]);
    }
    // A hidden flag of a layer.
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .transform(0, &[], 1, 3, &[])
        .shape(1, &[], &[0])
        .layer(3, &[("_hidden", "2")]);
    refused(&w.bytes(), &["layer 3", "'LAYR'", "_hidden"]);
    // Dictionary keys twice.
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .matl(1, &[("_rough", "0.5"), ("_rough", "0.2")]);
    refused(&w.bytes(), &["'MATL'", "\"_rough\" twice"]);
}

#[test]
fn bad_materials_are_refused() {
    for (properties, key) in [
        (&[("_type", "_metal"), ("_metal", "1.5")][..], "_metal"),
        (&[("_type", "_glass"), ("_trans", "-0.1")][..], "_trans"),
        (&[("_type", "_emit"), ("_emit", "NaN")][..], "_emit"),
        (&[("_type", "_emit"), ("_flux", "inf")][..], "_flux"),
        (&[("_rough", "rough")][..], "_rough"),
        (&[("_type", "_metal"), ("_metal", "NaN")][..], "_metal"),
        (&[("_type", "_metal"), ("_rough", "-inf")][..], "_rough"),
        (&[("_type", "_glass"), ("_alpha", "1.5")][..], "_alpha"),
        (&[("_type", "_glass"), ("_alpha", "nan")][..], "_alpha"),
        (&[("_type", "_emit"), ("_emit", "-0.5")][..], "_emit"),
        // Each value finite, their product not: no infinite light reaches a renderer or a
        // glTF file (where it would be written as `null`).
        (
            &[("_type", "_emit"), ("_emit", "2"), ("_flux", "3e38")][..],
            "2 x (1 + 300000000000000000000000000000000000000)",
        ),
        (
            &[("_type", "_blend"), ("_emit", "3e38"), ("_flux", "4")][..],
            "emission",
        ),
    ] {
        let mut w = VoxWriter::new();
        w.model([1, 1, 1], &[[0, 0, 0, 1]]).matl(9, properties);
        refused(&w.bytes(), &["material 9", "'MATL' at byte 64", key]);
    }
    for id in [-1, 257] {
        let mut w = VoxWriter::new();
        w.model([1, 1, 1], &[[0, 0, 0, 1]]).matl(id, &[]);
        refused(&w.bytes(), &["material id", &id.to_string()]);
    }
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .matl(4, &[])
        .matl(4, &[]);
    refused(&w.bytes(), &["defines material 4 a second time"]);
    // A MATT chunk whose values do not match its property bits, and one of an unknown type.
    let matt = |kind: u32, bits: u32, values: usize| {
        let mut c = 1i32.to_le_bytes().to_vec();
        c.extend(kind.to_le_bytes());
        c.extend(1f32.to_le_bytes());
        c.extend(bits.to_le_bytes());
        c.extend((0..values).flat_map(|_| 0.5f32.to_le_bytes()));
        c
    };
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .chunk(b"MATT", matt(0, 0b110, 1));
    refused(&w.bytes(), &["'MATT'", "holds 20 bytes", "0x6"]);
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .chunk(b"MATT", matt(7, 0, 0));
    refused(&w.bytes(), &["'MATT'", "material type", "7"]);
}

#[test]
fn voxels_leaving_the_world_and_scenes_over_the_limit_are_refused() {
    let mut w = VoxWriter::new();
    w.model([4, 4, 4], &[[0, 0, 0, 1], [3, 3, 3, 1]])
        .transform(0, &[], 1, -1, &[("_t", "2147483647 0 0")])
        .shape(1, &[], &[0]);
    let err = refused(
        &w.bytes(),
        &["model 0", "(3, 3, 3)", "outside the i32 world"],
    );
    assert!(matches!(err, VoxError::OutOfWorld { .. }));

    let bytes = two_model_scene().bytes();
    let err = load_vox_bytes(&bytes, ChunkSize::S16, 6).expect_err("7 voxels > 6");
    assert!(err.to_string().contains("allowed 6 voxels"), "{err}");
}

#[test]
fn random_corruptions_are_errors_or_scenes_never_panics() {
    // Every single-byte change of a valid scene: the loader answers without panicking, and
    // any scene it accepts is consistent.
    let bytes = two_model_scene().bytes();
    for at in 0..bytes.len() {
        for value in [0u8, 1, 0x7f, 0x80, 0xff] {
            let mut b = bytes.clone();
            b[at] = value;
            if let Ok(scene) = load(&b) {
                let stored: usize = scene
                    .world
                    .iter()
                    .map(|(_, c)| {
                        use voxel_core::storage::VoxelStorage;
                        c.non_air_count()
                    })
                    .sum();
                assert_eq!(stored, scene.voxel_count, "byte {at} = {value}");
            }
        }
    }
}
