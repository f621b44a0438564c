//! Vertical shells against a per-voxel reference: the runs cover exactly the exposed voxels,
//! never overlap, hold one id each, are maximal, and their side bits match the visible faces.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod surface_blocks_support;

use std::collections::{BTreeMap, BTreeSet};

use mesher::{BlockClasses, MeshError, ShellRun, ShellRuns, vertical_shells};
use proptest::prelude::*;
use surface_blocks_support::*;
use voxel_core::formats::FaceDirection;
use voxel_core::{BlockId, ChunkSize, PaddedChunk};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn runs_cover_exactly_the_exposed_voxels_with_the_right_sides(spec in chunk_spec()) {
        let palette = palette();
        let classes = BlockClasses::from_palette(&palette);
        let chunk = spec.build();
        let e = spec.size.edge();
        let mut out = ShellRuns::new();
        vertical_shells(&chunk, &classes, &mut out).unwrap();

        let faces: BTreeMap<[u32; 3], [bool; 6]> = positions(spec.size)
            .map(|pos| (pos, faces_of(&chunk, &palette, pos)))
            .filter(|(_, f)| f.contains(&true))
            .collect();
        let mut covered = BTreeSet::new();
        for run in out.runs() {
            let top = u32::from(run.y) + u32::from(run.height);
            prop_assert!(run.height >= 1 && top <= e, "{run:?}");
            prop_assert!(u32::from(run.x) < e && u32::from(run.z) < e, "{run:?}");
            prop_assert_eq!(run.wide, 0);
            let mut sides = [false; 6];
            for pos in run.voxels() {
                prop_assert!(covered.insert(pos), "{:?} in two runs", pos);
                prop_assert_eq!(id_at(&chunk, pos), run.block_id(), "{:?} in {:?}", pos, run);
                let f = faces.get(&pos);
                prop_assert!(f.is_some(), "{:?} of {:?} is not exposed", pos, run);
                for (s, f) in sides.iter_mut().zip(f.unwrap()) {
                    *s |= f;
                }
            }
            let bits = sides.iter().enumerate().fold(0u8, |acc, (d, &s)| acc | (u8::from(s) << d));
            prop_assert_eq!(run.sides, bits, "{:?}", run);
            // Maximal: the voxels just below and above are not exposed voxels of the same id.
            let (x, y, z) = (u32::from(run.x), u32::from(run.y), u32::from(run.z));
            let top = y + u32::from(run.height);
            let mut ends = vec![[x, top, z]];
            if y > 0 {
                ends.push([x, y - 1, z]);
            }
            for end in ends.into_iter().filter(|p| p[1] < e) {
                prop_assert!(
                    !(faces.contains_key(&end) && id_at(&chunk, end) == run.block_id()),
                    "{:?} could grow to {:?}", run, end
                );
            }
        }
        let exposed: BTreeSet<[u32; 3]> = faces.keys().copied().collect();
        prop_assert_eq!(covered, exposed);
    }

    #[test]
    fn a_reused_buffer_gives_what_a_fresh_one_gives(a in chunk_spec(), b in chunk_spec()) {
        let classes = BlockClasses::from_palette(&palette());
        let mut reused = ShellRuns::new();
        vertical_shells(&a.build(), &classes, &mut reused).unwrap();
        let chunk = b.build();
        vertical_shells(&chunk, &classes, &mut reused).unwrap();
        let mut fresh = ShellRuns::new();
        vertical_shells(&chunk, &classes, &mut fresh).unwrap();
        prop_assert_eq!(reused.runs(), fresh.runs());
    }

    #[test]
    fn exposed_unknown_ids_are_errors_and_leave_the_buffer_empty(
        size in size(),
        at in any::<[u32; 3]>(),
    ) {
        let classes = BlockClasses::from_palette(&palette());
        let e = size.edge();
        let at = at.map(|a| a % e + 1);
        let floor = PaddedChunk::from_fn(size, |_, y, _| if y == 1 { STONE } else { BlockId::AIR });
        let chunk = PaddedChunk::from_fn(size, |x, y, z| {
            if [x, y, z] == at { UNKNOWN } else if y <= at[1] { STONE } else { BlockId::AIR }
        });
        let mut out = ShellRuns::new();
        vertical_shells(&floor, &classes, &mut out).unwrap();
        prop_assert!(!out.is_empty());
        let result = vertical_shells(&chunk, &classes, &mut out);
        prop_assert_eq!(result, Err(MeshError::UnknownBlock { id: UNKNOWN, position: at }));
        prop_assert!(out.is_empty());
    }
}

#[test]
fn shell_run_is_8_bytes_read_as_two_words() {
    let run = ShellRun {
        x: 1,
        z: 2,
        y: 3,
        height: 62,
        block: 0xBEEF,
        sides: 0b10_0101,
        wide: 0,
    };
    assert_eq!(size_of::<ShellRun>(), 8);
    assert_eq!(ShellRun::new(1, 2, 3, 62, 0xBEEF, 0b10_0101), run);
    let words: [u32; 2] = bytemuck::cast(run);
    assert_eq!(words[0], 1 | 2 << 8 | 3 << 16 | 62 << 24);
    assert_eq!(words[1], 0xBEEF | 0b10_0101 << 16);
    assert_eq!(ShellRun::WGSL_LAYOUT.size, 8);
    let offsets: Vec<usize> = ShellRun::WGSL_LAYOUT
        .members
        .iter()
        .map(|m| m.offset)
        .collect();
    assert_eq!(offsets, [0, 4]);
    assert!(run.has_side(FaceDirection::PosX) && run.has_side(FaceDirection::PosY));
    assert!(run.has_side(FaceDirection::NegZ) && !run.has_side(FaceDirection::NegX));
}

#[test]
fn a_hillside_column_splits_by_id_and_skips_buried_voxels() {
    // Column (3, 3) of an 8^3 chunk: dirt at y 0..4, grass at y 4, air above; the columns around
    // it are stone up to y 2 (so dirt y 0..=1 is buried on its sides) and the chunk below is
    // stone (so dirt y 0 is buried).
    let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
        let (in_column, ly) = ((x, z) == (4, 4), y as i32 - 1);
        match (in_column, ly) {
            (_, -1) => STONE,
            (true, 0..=3) => DIRT,
            (true, 4) => GRASS,
            (false, 0..=1) => STONE,
            _ => BlockId::AIR,
        }
    });
    let classes = BlockClasses::from_palette(&palette());
    let mut out = ShellRuns::new();
    vertical_shells(&chunk, &classes, &mut out).unwrap();
    let column: Vec<ShellRun> = out
        .runs()
        .iter()
        .copied()
        .filter(|r| (r.x, r.z) == (3, 3))
        .collect();
    let sides = 0b11_0011; // +x, -x, +z, -z
    let up = 1 << FaceDirection::PosY.index();
    assert_eq!(
        column,
        [
            ShellRun {
                x: 3,
                z: 3,
                y: 2,
                height: 2,
                block: DIRT.0,
                sides,
                wide: 0
            },
            ShellRun {
                x: 3,
                z: 3,
                y: 4,
                height: 1,
                block: GRASS.0,
                sides: sides | up,
                wide: 0
            },
        ]
    );
}

#[test]
fn empty_and_buried_full_chunks_give_no_runs() {
    let classes = BlockClasses::from_palette(&palette());
    let mut out = ShellRuns::new();
    for size in ChunkSize::ALL {
        let p = size.padded_edge() as u32;
        let border = |x: u32, y: u32, z: u32| [x, y, z].iter().any(|&a| a == 0 || a == p - 1);
        let empty = PaddedChunk::from_fn(
            size,
            |x, y, z| if border(x, y, z) { STONE } else { BlockId::AIR },
        );
        vertical_shells(&empty, &classes, &mut out).unwrap();
        assert!(out.is_empty(), "{size:?}");
        for id in [STONE, WATER] {
            vertical_shells(
                &PaddedChunk::from_fn(size, |_, _, _| id),
                &classes,
                &mut out,
            )
            .unwrap();
            assert!(out.is_empty(), "{size:?} {id:?}");
        }
        // A full column of stone in open air is one run of the whole height.
        let e = size.edge();
        let pillar = PaddedChunk::from_fn(size, |x, y, z| {
            if (x, z) == (1, 1) && (1..=e).contains(&y) {
                STONE
            } else {
                BlockId::AIR
            }
        });
        vertical_shells(&pillar, &classes, &mut out).unwrap();
        assert_eq!(
            out.runs(),
            [ShellRun {
                x: 0,
                z: 0,
                y: 0,
                height: e as u8,
                block: STONE.0,
                sides: 0b11_1111,
                wide: 0
            }]
        );
    }
}
