//! World / chunk / local coordinates over the whole i32 range.

use proptest::prelude::*;
use voxel_core::{ChunkCoord, ChunkSize, CoordError, LocalPos, WorldPos};

/// An i32 that is often one of the interesting values.
fn axis() -> impl Strategy<Value = i32> {
    prop_oneof![
        1 => Just(i32::MIN),
        1 => Just(i32::MIN + 1),
        1 => Just(i32::MAX),
        1 => Just(i32::MAX - 1),
        1 => Just(-1),
        1 => Just(0),
        1 => Just(1),
        4 => any::<i32>(),
        2 => -200i32..200,
    ]
}

fn size() -> impl Strategy<Value = ChunkSize> {
    prop::sample::select(ChunkSize::ALL.to_vec())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// `split` then `world_pos` gives the position back; the parts match i64 Euclidean division.
    #[test]
    fn split_round_trips(x in axis(), y in axis(), z in axis(), size in size()) {
        let pos = WorldPos::new(x, y, z);
        let (chunk, local) = pos.split(size);
        let e = i64::from(size.edge());
        for (w, c, l) in [(x, chunk.x, local.x), (y, chunk.y, local.y), (z, chunk.z, local.z)] {
            prop_assert_eq!(i64::from(c), i64::from(w).div_euclid(e));
            prop_assert_eq!(i64::from(l), i64::from(w).rem_euclid(e));
            prop_assert_eq!(i64::from(c) * e + i64::from(l), i64::from(w));
        }
        prop_assert_eq!(local.check(size), Ok(()));
        prop_assert_eq!(chunk.world_pos(local, size), Ok(pos));
        let (lo, hi) = ChunkCoord::valid_range(size);
        for c in [chunk.x, chunk.y, chunk.z] {
            prop_assert!(lo <= c && c <= hi);
        }
    }

    /// `world_pos` is Ok exactly when the voxel lies inside the i32 range.
    #[test]
    fn world_pos_is_checked(
        cx in axis(), cy in axis(), cz in axis(), size in size(),
        lx in 0u32..62, ly in 0u32..62, lz in 0u32..62,
    ) {
        let e = size.edge();
        let (lx, ly, lz) = (lx % e, ly % e, lz % e);
        let chunk = ChunkCoord::new(cx, cy, cz);
        let local = LocalPos::new(lx, ly, lz, size).unwrap();
        let wide = [(cx, lx), (cy, ly), (cz, lz)].map(|(c, l)| i64::from(c) * i64::from(e) + i64::from(l));
        match wide.map(i32::try_from) {
            [Ok(x), Ok(y), Ok(z)] => prop_assert_eq!(chunk.world_pos(local, size), Ok(WorldPos::new(x, y, z))),
            _ => prop_assert_eq!(
                chunk.world_pos(local, size),
                Err(CoordError::ChunkOutOfWorld { chunk, edge: e })
            ),
        }
    }

    /// Offsets are exact or an error, never wrapped.
    #[test]
    fn checked_offsets_never_wrap(x in axis(), y in axis(), z in axis(), d in [axis(), axis(), axis()]) {
        let sum = [(x, d[0]), (y, d[1]), (z, d[2])].map(|(a, b)| i32::try_from(i64::from(a) + i64::from(b)));
        let chunk = ChunkCoord::new(x, y, z);
        let world = WorldPos::new(x, y, z);
        match sum {
            [Ok(a), Ok(b), Ok(c)] => {
                prop_assert_eq!(chunk.checked_offset(d), Ok(ChunkCoord::new(a, b, c)));
                prop_assert_eq!(world.checked_offset(d), Ok(WorldPos::new(a, b, c)));
            }
            _ => {
                prop_assert_eq!(chunk.checked_offset(d), Err(CoordError::ChunkOverflow { chunk, offset: d }));
                prop_assert_eq!(world.checked_offset(d), Err(CoordError::WorldOverflow { pos: world, offset: d }));
            }
        }
    }
}

#[test]
fn negative_positions_land_in_negative_chunks() {
    for size in ChunkSize::ALL {
        let e = size.edge() as i32;
        let last = (e - 1) as u8;
        let (c, l) = WorldPos::new(-1, -1, -1).split(size);
        assert_eq!(c, ChunkCoord::new(-1, -1, -1));
        assert_eq!((l.x, l.y, l.z), (last, last, last));
        let (c, l) = WorldPos::new(-e, -e - 1, e).split(size);
        assert_eq!(c, ChunkCoord::new(-1, -2, 1));
        assert_eq!((l.x, l.y, l.z), (0, last, 0));
        let (c, l) = WorldPos::new(0, e - 1, 1).split(size);
        assert_eq!(c, ChunkCoord::new(0, 0, 0));
        assert_eq!((l.x, l.y, l.z), (0, last, 1));
    }
}

#[test]
fn last_chunks_of_size_62_are_partly_outside_i32() {
    let size = ChunkSize::S62;
    let (lo, hi) = ChunkCoord::valid_range(size);
    assert_eq!((lo, hi), (-34_636_834, 34_636_833));
    // Top: chunk `hi` starts at 2_147_483_646; locals 0 and 1 are inside, 2.. are past MAX.
    let top = ChunkCoord::new(hi, 0, 0);
    let at = |x: u32| LocalPos::new(x, 0, 0, size).unwrap();
    assert_eq!(top.origin(size), Ok(WorldPos::new(2_147_483_646, 0, 0)));
    assert_eq!(
        top.world_pos(at(1), size),
        Ok(WorldPos::new(i32::MAX, 0, 0))
    );
    let outside = Err(CoordError::ChunkOutOfWorld {
        chunk: top,
        edge: 62,
    });
    assert_eq!(top.world_pos(at(2), size), outside);
    assert_eq!(top.world_pos(at(61), size), outside);
    // Bottom: chunk `lo` starts at -2_147_483_708, 60 below MIN; locals 60 and 61 are inside.
    let bottom = ChunkCoord::new(0, lo, 0);
    let at_y = |y: u32| LocalPos::new(0, y, 0, size).unwrap();
    let below = Err(CoordError::ChunkOutOfWorld {
        chunk: bottom,
        edge: 62,
    });
    assert_eq!(bottom.origin(size), below);
    assert_eq!(bottom.world_pos(at_y(59), size), below);
    assert_eq!(
        bottom.world_pos(at_y(60), size),
        Ok(WorldPos::new(0, i32::MIN, 0))
    );
    assert_eq!(
        bottom.world_pos(at_y(61), size),
        Ok(WorldPos::new(0, i32::MIN + 1, 0))
    );
    // Chunks past the valid range hold no i32 position at all.
    for local in [at(0), at(61)] {
        assert!(
            ChunkCoord::new(hi + 1, 0, 0)
                .world_pos(local, size)
                .is_err()
        );
        assert!(
            ChunkCoord::new(lo - 1, 0, 0)
                .world_pos(local, size)
                .is_err()
        );
    }
    // Power-of-two sizes tile the i32 range exactly.
    for size in [ChunkSize::S8, ChunkSize::S16, ChunkSize::S32] {
        let (lo, hi) = ChunkCoord::valid_range(size);
        assert_eq!(
            ChunkCoord::new(lo, lo, lo).origin(size),
            Ok(WorldPos::new(i32::MIN, i32::MIN, i32::MIN))
        );
        let last = LocalPos::new(size.edge() - 1, 0, 0, size).unwrap();
        assert_eq!(
            ChunkCoord::new(hi, 0, 0).world_pos(last, size),
            Ok(WorldPos::new(i32::MAX, 0, 0))
        );
    }
}

#[test]
fn checked_offset_overflow_is_an_error() {
    let max = ChunkCoord::new(i32::MAX, 0, i32::MIN);
    assert_eq!(
        max.checked_offset([1, 0, 0]),
        Err(CoordError::ChunkOverflow {
            chunk: max,
            offset: [1, 0, 0]
        })
    );
    assert!(max.checked_offset([0, 0, -1]).is_err());
    assert_eq!(
        max.checked_offset([-1, 0, 1]),
        Ok(ChunkCoord::new(i32::MAX - 1, 0, i32::MIN + 1))
    );
    let pos = WorldPos::new(i32::MIN, 0, 0);
    assert!(pos.checked_offset([-1, 0, 0]).is_err());
    assert!(pos.checked_offset([0, i32::MAX, 0]).is_ok());
    assert!(
        WorldPos::new(0, 1, 0)
            .checked_offset([0, i32::MAX, 0])
            .is_err()
    );
}

#[test]
fn local_pos_rejects_the_edge() {
    for size in ChunkSize::ALL {
        let e = size.edge();
        assert!(LocalPos::new(e - 1, e - 1, e - 1, size).is_ok());
        for pos in [
            [e, 0, 0],
            [0, e, 0],
            [0, 0, e],
            [u32::MAX, 0, 0],
            [0, 300, 0],
        ] {
            assert_eq!(
                LocalPos::new(pos[0], pos[1], pos[2], size),
                Err(CoordError::LocalOutOfChunk { pos, edge: e })
            );
        }
        // A position valid for a bigger chunk fails `check` and `index` on a smaller one.
        let big = LocalPos::new(61, 0, 0, ChunkSize::S62).unwrap();
        if size != ChunkSize::S62 {
            assert!(big.check(size).is_err());
            assert!(big.index(size).is_err());
        } else {
            assert_eq!(big.index(size), Ok(61));
        }
    }
}
