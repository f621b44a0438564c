//! `gather_neighbourhood` against a brute-force reference over the padded box, for random worlds
//! with random missing neighbours, including chunks at the i32 extremes of chunk coordinates.

mod storage_support;

use proptest::prelude::*;
use storage_support::Rng;
use voxel_core::storage::{
    DenseChunk, PaddedChunk, PaletteChunk, VoxelStorage, WorldMap, gather_neighbourhood,
};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos, WorldPos};

/// A chunk axis: small, or at / next to the i32 extremes.
fn chunk_axis() -> impl Strategy<Value = i32> {
    prop_oneof![
        3 => -3i32..3,
        1 => Just(i32::MIN),
        1 => Just(i32::MIN + 1),
        1 => Just(i32::MAX),
        1 => Just(i32::MAX - 1),
        1 => any::<i32>(),
    ]
}

fn size() -> impl Strategy<Value = ChunkSize> {
    prop::sample::select(ChunkSize::ALL.to_vec())
}

/// Random chunk content: uniform air or solid, sparse, dense, or many ids (raw palette).
fn random_chunk(size: ChunkSize, rng: &mut Rng) -> DenseChunk {
    match rng.below(5) {
        0 => DenseChunk::new(size),
        1 => DenseChunk::filled(size, BlockId(1 + rng.below(5) as u16)),
        kind => {
            let density = 1 + rng.below(100);
            let ids = if kind == 4 { 1000 } else { 1 + rng.below(6) };
            let mut local = Rng::new(rng.next_u64());
            DenseChunk::from_fn(size, |_| {
                if local.below(100) < density {
                    BlockId(1 + local.below(ids) as u16)
                } else {
                    BlockId::AIR
                }
            })
        }
    }
}

/// Two worlds holding the same voxels around `centre`: dense chunks, and palette chunks (built
/// from dense, or by single writes so their widths and free entries differ).
fn random_worlds(
    size: ChunkSize,
    centre: ChunkCoord,
    seed: u64,
) -> (WorldMap<DenseChunk>, WorldMap<PaletteChunk>) {
    let mut rng = Rng::new(seed);
    let mut dense_world = WorldMap::new(size);
    let mut palette_world: WorldMap = WorldMap::new(size);
    for dz in -1..=1 {
        for dy in -1..=1 {
            for dx in -1..=1 {
                let Ok(coord) = centre.checked_offset([dx, dy, dz]) else {
                    continue;
                };
                if rng.below(3) == 0 {
                    continue; // missing neighbour
                }
                let dense = random_chunk(size, &mut rng);
                let palette = if rng.below(2) == 0 {
                    PaletteChunk::from_dense(&dense)
                } else {
                    let mut p = PaletteChunk::new(size);
                    for (pos, id) in dense.iter() {
                        p.set(pos, id).unwrap();
                    }
                    p
                };
                dense_world.insert(coord, dense).unwrap();
                palette_world.insert(coord, palette).unwrap();
            }
        }
    }
    (dense_world, palette_world)
}

/// The padded box read voxel by voxel: world coordinates in i64, chunk by Euclidean division,
/// air where the chunk is missing or its coordinate is not an i32. Where the world position
/// fits in i32, `WorldMap::get_block` must agree.
fn reference<C: VoxelStorage>(world: &WorldMap<C>, centre: ChunkCoord) -> Vec<BlockId> {
    let size = world.size();
    let e = i64::from(size.edge());
    let p = size.padded_edge() as i64;
    let base = [centre.x, centre.y, centre.z].map(|c| i64::from(c) * e - 1);
    let mut out = Vec::with_capacity((p * p * p) as usize);
    for pz in 0..p {
        for py in 0..p {
            for px in 0..p {
                let g = [base[0] + px, base[1] + py, base[2] + pz];
                let chunk = g.map(|a| i32::try_from(a.div_euclid(e)));
                let local = g.map(|a| a.rem_euclid(e) as u8);
                let id = match chunk {
                    [Ok(x), Ok(y), Ok(z)] => world
                        .get(ChunkCoord::new(x, y, z))
                        .map(|c| {
                            let pos = LocalPos {
                                x: local[0],
                                y: local[1],
                                z: local[2],
                            };
                            c.get(pos).unwrap()
                        })
                        .unwrap_or(BlockId::AIR),
                    _ => BlockId::AIR,
                };
                if let [Ok(x), Ok(y), Ok(z)] = g.map(i32::try_from) {
                    assert_eq!(world.get_block(WorldPos::new(x, y, z)), id);
                }
                out.push(id);
            }
        }
    }
    out
}

fn check_gather<C: VoxelStorage>(
    world: &WorldMap<C>,
    centre: ChunkCoord,
    out: &mut PaddedChunk,
) -> Result<(), TestCaseError> {
    gather_neighbourhood(world, centre, out);
    let size = world.size();
    let p = size.padded_edge();
    prop_assert_eq!(out.size(), size);
    prop_assert_eq!(out.voxels().len(), p * p * p);
    prop_assert_eq!(out.columns().len(), p * p);
    let expect = reference(world, centre);
    for (i, (got, want)) in out.voxels().iter().zip(&expect).enumerate() {
        prop_assert_eq!(
            got,
            want,
            "padded ({}, {}, {})",
            i % p,
            i / p % p,
            i / (p * p)
        );
    }
    for (c, &mask) in out.columns().iter().enumerate() {
        let row = &out.voxels()[c * p..(c + 1) * p];
        let recount = row
            .iter()
            .enumerate()
            .fold(0u64, |m, (x, v)| m | (u64::from(!v.is_air()) << x));
        prop_assert_eq!(mask, recount, "padded row ({}, {})", c % p, c / p);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn gather_equals_brute_force(
        size in size(),
        x in chunk_axis(), y in chunk_axis(), z in chunk_axis(),
        seed in any::<u64>(),
        stale in size(),
    ) {
        let centre = ChunkCoord::new(x, y, z);
        let (dense_world, palette_world) = random_worlds(size, centre, seed);
        // Start from a buffer of another size full of junk: the gather must overwrite it all.
        let mut junk = Rng::new(seed ^ 0x5EED);
        let mut out = PaddedChunk::from_fn(stale, |_, _, _| BlockId(junk.below(3) as u16));
        check_gather(&dense_world, centre, &mut out)?;
        let dense_result = out.clone();
        check_gather(&palette_world, centre, &mut out)?;
        prop_assert_eq!(&out, &dense_result);
    }
}

#[test]
fn missing_world_gathers_all_air() {
    for size in ChunkSize::ALL {
        let world: WorldMap = WorldMap::new(size);
        let mut out = PaddedChunk::from_fn(size, |_, _, _| BlockId(1));
        gather_neighbourhood(&world, ChunkCoord::new(i32::MAX, i32::MIN, 0), &mut out);
        assert!(out.voxels().iter().all(|v| v.is_air()));
        assert!(out.columns().iter().all(|&m| m == 0));
        assert_eq!(out, PaddedChunk::new(size));
    }
}

#[test]
fn corners_edges_and_faces_land_where_the_diagram_says() {
    let size = ChunkSize::S62;
    let mut world: WorldMap = WorldMap::new(size);
    let e = size.edge() as i32;
    // One marker per neighbour, in the voxel that touches the centre chunk.
    for dz in -1..=1i32 {
        for dy in -1..=1i32 {
            for dx in -1..=1i32 {
                let pick = |d: i32| match d {
                    -1 => -1,
                    0 => 5,
                    _ => e,
                };
                let id = BlockId((1 + (dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)) as u16);
                world.set_block(WorldPos::new(pick(dx), pick(dy), pick(dz)), id);
            }
        }
    }
    let mut out = PaddedChunk::new(size);
    gather_neighbourhood(&world, ChunkCoord::new(0, 0, 0), &mut out);
    for dz in -1..=1i32 {
        for dy in -1..=1i32 {
            for dx in -1..=1i32 {
                let pick = |d: i32| match d {
                    -1 => 0u32,
                    0 => 6,
                    _ => e as u32 + 1,
                };
                let id = BlockId((1 + (dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)) as u16);
                assert_eq!(
                    out.get(pick(dx), pick(dy), pick(dz)),
                    Ok(id),
                    "{dx} {dy} {dz}"
                );
                let mask = out.column(pick(dy), pick(dz)).unwrap();
                assert_ne!(mask & (1 << pick(dx)), 0);
            }
        }
    }
    assert_eq!(out.voxels().iter().filter(|v| !v.is_air()).count(), 27);
    assert!(out.get(64, 0, 0).is_err());
    assert!(out.column(0, 64).is_err());
}
