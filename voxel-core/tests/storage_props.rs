//! Palette storage against dense storage under random edits; occupancy masks, counts and
//! conversions against brute-force recounts; out-of-range access as errors.

mod storage_support;

use proptest::prelude::*;
use storage_support::{
    Op, check_consistent, distinct, run_script, script, smallest_bits, voxels_by_get,
};
use voxel_core::storage::{DenseChunk, PaletteChunk, StorageError, VoxelStorage};
use voxel_core::{BlockId, ChunkSize, CoordError, LocalPos};

/// Pools chosen to reach every width: 2 ids (1 bit), 4 (2), 16 (4), 200 (8), 1000 (16 raw).
fn pool() -> impl Strategy<Value = u64> {
    prop_oneof![Just(2u64), Just(4), Just(16), Just(200), Just(1000)]
}

fn size() -> impl Strategy<Value = ChunkSize> {
    prop::sample::select(ChunkSize::ALL.to_vec())
}

fn check_pair(dense: &DenseChunk, palette: &PaletteChunk) -> Result<(), TestCaseError> {
    let d = voxels_by_get(dense);
    let p = voxels_by_get(palette);
    prop_assert!(d == p, "palette storage differs from dense storage");
    prop_assert_eq!(dense.as_slice(), &d[..]);
    check_consistent(dense).map_err(|e| TestCaseError::fail(format!("dense: {e}")))?;
    check_consistent(palette).map_err(|e| TestCaseError::fail(format!("palette: {e}")))?;
    // Writes only ever grow the width, so it is at least the smallest for the ids present.
    prop_assert!(palette.bits_per_voxel() >= smallest_bits(distinct(&d)));
    prop_assert_eq!(palette.distinct_ids(), distinct(&d));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Thousands of set / fill / box edits give the same voxels, old ids, masks and counts.
    #[test]
    fn palette_equals_dense_under_random_edits(
        size in size(), pool in pool(), seed in any::<u64>(), n in 500usize..3000,
    ) {
        let ops = script(seed, size, pool, n);
        let (dense, palette) = run_script(size, &ops).map_err(TestCaseError::fail)?;
        check_pair(&dense, &palette)?;
    }

    /// Conversions both ways keep every voxel; the palette built from dense has the smallest
    /// width, and `compact` reaches it too.
    #[test]
    fn conversions_preserve_every_voxel(
        size in size(), pool in pool(), seed in any::<u64>(), n in 0usize..2500,
    ) {
        let ops = script(seed, size, pool, n);
        let (dense, mut palette) = run_script(size, &ops).map_err(TestCaseError::fail)?;
        let voxels = voxels_by_get(&dense);
        let from_dense = PaletteChunk::from_dense(&dense);
        prop_assert_eq!(voxels_by_get(&from_dense), voxels.clone());
        prop_assert_eq!(from_dense.bits_per_voxel(), smallest_bits(distinct(&voxels)));
        check_consistent(&from_dense).map_err(TestCaseError::fail)?;
        let back = DenseChunk::from_palette(&palette);
        prop_assert_eq!(&back, &dense);
        prop_assert_eq!(DenseChunk::from(&from_dense), dense.clone());
        palette.compact();
        prop_assert_eq!(voxels_by_get(&palette), voxels.clone());
        prop_assert_eq!(palette.bits_per_voxel(), smallest_bits(distinct(&voxels)));
        prop_assert_eq!(palette.palette().len(), if palette.bits_per_voxel() == 16 { 0 } else { distinct(&voxels) });
        check_consistent(&palette).map_err(TestCaseError::fail)?;
        // And the compacted chunk keeps working under more edits.
        let more = script(seed ^ 1, size, pool, 300);
        let (mut d2, mut p2) = (dense.clone(), palette.clone());
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for op in more {
            storage_support::apply(&mut d2, op, &mut a);
            storage_support::apply(&mut p2, op, &mut b);
            prop_assert_eq!(&a, &b);
        }
        check_pair(&d2, &p2)?;
    }

    /// Any position outside the chunk is an error from every accessor, never a panic.
    #[test]
    fn out_of_range_positions_are_errors(
        size in size(), x in 0u32..62, y in 0u32..62, z in 0u32..62,
    ) {
        let pos = LocalPos::new(x, y, z, ChunkSize::S62).unwrap();
        let e = size.edge();
        let inside = x < e && y < e && z < e;
        let mut dense = DenseChunk::new(size);
        let mut palette = PaletteChunk::new(size);
        let expect = CoordError::LocalOutOfChunk { pos: [x, y, z], edge: e };
        if inside {
            prop_assert_eq!(dense.set(pos, BlockId(3)), Ok(BlockId::AIR));
            prop_assert_eq!(palette.set(pos, BlockId(3)), Ok(BlockId::AIR));
            prop_assert_eq!(palette.get(pos), Ok(BlockId(3)));
        } else {
            prop_assert_eq!(dense.get(pos), Err(expect));
            prop_assert_eq!(dense.set(pos, BlockId(3)), Err(expect));
            prop_assert_eq!(palette.get(pos), Err(expect));
            prop_assert_eq!(palette.set(pos, BlockId(3)), Err(expect));
            prop_assert_eq!(dense.non_air_count(), 0);
            prop_assert_eq!(palette.non_air_count(), 0);
        }
        let row_ok = y < e && z < e;
        let mut row = vec![BlockId::AIR; e as usize];
        prop_assert_eq!(dense.column_mask(y, z).is_ok(), row_ok);
        prop_assert_eq!(palette.column_mask(y, z).is_ok(), row_ok);
        prop_assert_eq!(dense.copy_row(y, z, &mut row).is_ok(), row_ok);
        prop_assert_eq!(palette.copy_row(y, z, &mut row).is_ok(), row_ok);
    }
}

#[test]
fn rows_of_the_wrong_length_are_errors() {
    for size in ChunkSize::ALL {
        let e = size.edge_usize();
        let dense = DenseChunk::new(size);
        let palette = PaletteChunk::new(size);
        for len in [0, e - 1, e + 1] {
            let mut row = vec![BlockId::AIR; len];
            let expect = Err(StorageError::WrongLength {
                expected: e,
                got: len,
            });
            assert_eq!(dense.copy_row(0, 0, &mut row), expect);
            assert_eq!(palette.copy_row(0, 0, &mut row), expect);
        }
        assert_eq!(
            DenseChunk::from_voxels(size, vec![BlockId::AIR; 7]),
            Err(StorageError::WrongLength {
                expected: size.volume(),
                got: 7
            })
        );
    }
}

/// Adding ids one by one walks through every width: 0 -> 1 -> 2 -> 4 -> 8 -> 16 bits.
#[test]
fn widths_grow_through_every_step_and_fill_collapses() {
    for size in ChunkSize::ALL {
        let mut chunk = PaletteChunk::new(size);
        let mut seen = vec![chunk.bits_per_voxel()];
        for id in 1..=300u16 {
            let pos = LocalPos::new(
                u32::from(id) % size.edge(),
                u32::from(id) / size.edge() % size.edge(),
                u32::from(id) / (size.edge() * size.edge()),
                size,
            )
            .unwrap();
            chunk.set(pos, BlockId(id)).unwrap();
            if seen.last() != Some(&chunk.bits_per_voxel()) {
                seen.push(chunk.bits_per_voxel());
            }
        }
        assert_eq!(seen, [0, 1, 2, 4, 8, 16], "size {size:?}");
        check_consistent(&chunk).unwrap();
        chunk.fill(BlockId(5));
        assert_eq!(chunk.bits_per_voxel(), 0);
        assert_eq!(chunk.uniform(), Some(BlockId(5)));
        assert_eq!(chunk.heap_bytes(), 0);
        assert_eq!(chunk.non_air_count(), size.volume());
    }
}

/// A chunk whose every voxel comes to hold one id collapses to uniform, from every width.
#[test]
fn covering_the_chunk_with_one_id_collapses_to_uniform() {
    for size in ChunkSize::ALL {
        for ids in [2u16, 4, 16, 256, 300] {
            let mut chunk = PaletteChunk::new(size);
            for i in 0..size.volume() {
                let pos = index_pos(size, i);
                chunk.set(pos, BlockId(i as u16 % ids)).unwrap();
            }
            assert_eq!(
                chunk.bits_per_voxel(),
                smallest_bits(usize::from(ids)),
                "size {size:?} ids {ids}"
            );
            for i in 0..size.volume() {
                assert_eq!(chunk.uniform(), None, "collapsed early at voxel {i}");
                chunk.set(index_pos(size, i), BlockId(9)).unwrap();
            }
            assert_eq!(chunk.uniform(), Some(BlockId(9)), "size {size:?} ids {ids}");
            assert_eq!(chunk.heap_bytes(), 0);
        }
    }
}

/// Entries freed by their last voxel are reused instead of growing the palette.
#[test]
fn freed_palette_entries_are_reused() {
    let size = ChunkSize::S16;
    let mut chunk = PaletteChunk::new(size);
    let a = index_pos(size, 10);
    let b = index_pos(size, 20);
    chunk.set(a, BlockId(1)).unwrap();
    assert_eq!(chunk.bits_per_voxel(), 1);
    // The only voxel of id 1 becomes id 2: id 1's entry is taken over, width stays 1.
    chunk.set(a, BlockId(2)).unwrap();
    assert_eq!((chunk.bits_per_voxel(), chunk.palette().len()), (1, 2));
    for id in 3..200 {
        chunk.set(a, BlockId(id)).unwrap();
    }
    assert_eq!((chunk.bits_per_voxel(), chunk.palette().len()), (1, 2));
    // A third id while two are live widens to 2 bits; freeing one then lets a fourth reuse it.
    chunk.set(b, BlockId(500)).unwrap();
    assert_eq!((chunk.bits_per_voxel(), chunk.palette().len()), (2, 3));
    chunk.set(b, BlockId::AIR).unwrap();
    chunk.set(b, BlockId(600)).unwrap();
    assert_eq!((chunk.bits_per_voxel(), chunk.palette().len()), (2, 3));
    check_consistent(&chunk).unwrap();
}

/// The storages report the ops they saw through `Op`, keeping the helper in use.
#[test]
fn fill_ops_reset_both_storages() {
    let ops = [
        Op::Set(LocalPos::default(), BlockId(4)),
        Op::Fill(BlockId::AIR),
    ];
    let (dense, palette) = run_script(ChunkSize::S8, &ops).unwrap();
    assert_eq!(dense.non_air_count(), 0);
    assert_eq!(palette.uniform(), Some(BlockId::AIR));
}

fn index_pos(size: ChunkSize, i: usize) -> LocalPos {
    let e = size.edge_usize();
    LocalPos::new(
        (i % e) as u32,
        (i / e % e) as u32,
        (i / (e * e)) as u32,
        size,
    )
    .unwrap()
}
