//! LOD downsampling against a plain per-voxel reference over random worlds.

use mesher::BlockClasses;
use mesher::lod::downsample_world;
use proptest::prelude::*;
use voxel_core::storage::{VoxelStorage, WorldMap};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, Material, MaterialClass, MaterialPalette, WorldPos,
};

fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(1, 1, 1)).unwrap(); // 1
    p.push(Material::opaque(2, 2, 2)).unwrap(); // 2
    p.push(Material::opaque(3, 3, 3).with_class(MaterialClass::Transparent))
        .unwrap(); // 3
    p.push(Material::opaque(4, 4, 4).with_class(MaterialClass::Smoothable))
        .unwrap(); // 4
    p
}

/// The rule of `mesher::lod`, written per voxel from world reads: the upper half decides when
/// it holds anything, opaque before transparent, then the most common id, ties to the smaller.
fn reference(children: [BlockId; 8], classes: &BlockClasses) -> BlockId {
    let half: &[BlockId] = if children[4..].iter().any(|c| !c.is_air()) {
        &children[4..]
    } else {
        &children[..4]
    };
    let candidates = |transparent: bool| {
        half.iter()
            .copied()
            .filter(move |&id| !id.is_air() && classes.is_transparent(id) == transparent)
    };
    for transparent in [false, true] {
        let best = candidates(transparent).max_by_key(|&id| {
            let count = half.iter().filter(|&&c| c == id).count();
            (count, std::cmp::Reverse(id))
        });
        if let Some(id) = best {
            return id;
        }
    }
    BlockId::AIR
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn coarse_voxels_follow_the_rule_and_keep_every_thin_surface(
        seed in any::<u64>(),
        density in 0.0f64..0.6,
        origin in prop_oneof![Just(0i32), Just(-1), Just(i32::MAX / 8 - 2), Just(i32::MIN / 8)],
    ) {
        let size = ChunkSize::S8;
        let classes = BlockClasses::from_palette(&palette());
        let mut world: WorldMap = WorldMap::new(size);
        let mut state = seed | 1;
        let mut next = || { state ^= state << 13; state ^= state >> 7; state ^= state << 17; state };
        // A random 3 x 2 x 2 block of finer chunks (some missing), around `origin` in chunk units.
        for cz in 0..2 {
            for cy in 0..2 {
                for cx in 0..3 {
                    if next() % 5 == 0 { continue; }
                    let coord = ChunkCoord::new(origin + cx, origin + cy, origin + cz);
                    let base = coord.origin(size).unwrap();
                    for i in 0..size.volume() as i32 {
                        if (next() % 1000) as f64 >= density * 1000.0 { continue; }
                        let id = BlockId((next() % 4 + 1) as u16);
                        let p = WorldPos::new(base.x + i % 8, base.y + i / 8 % 8, base.z + i / 64);
                        world.set_block(p, id);
                    }
                }
            }
        }
        let coarse = downsample_world(&world, &classes).unwrap();
        let (lo, hi) = (origin.div_euclid(2), (origin + 3).div_euclid(2));
        for cz in lo..=hi { for cy in lo..=hi { for cx in lo..=hi {
            let chunk = ChunkCoord::new(cx, cy, cz);
            let base = chunk.origin(size).unwrap();
            for i in 0..size.volume() as i32 {
                let (x, y, z) = (i % 8, i / 8 % 8, i / 64);
                let coarse_pos = WorldPos::new(base.x + x, base.y + y, base.z + z);
                // Fine world position of child (0,0,0): twice the coarse position.
                let fine = |dx: i32, dy: i32, dz: i32| {
                    let (fx, fy, fz) = (i64::from(coarse_pos.x) * 2 + i64::from(dx), i64::from(coarse_pos.y) * 2 + i64::from(dy), i64::from(coarse_pos.z) * 2 + i64::from(dz));
                    match (i32::try_from(fx), i32::try_from(fy), i32::try_from(fz)) {
                        (Ok(x), Ok(y), Ok(z)) => world.get_block(WorldPos::new(x, y, z)),
                        _ => BlockId::AIR,
                    }
                };
                let children = [fine(0,0,0), fine(1,0,0), fine(0,0,1), fine(1,0,1), fine(0,1,0), fine(1,1,0), fine(0,1,1), fine(1,1,1)];
                let got = coarse.get_block(coarse_pos);
                prop_assert_eq!(got, reference(children, &classes), "coarse {:?}", coarse_pos);
                // Thin surfaces survive: air only where every child is air.
                prop_assert_eq!(got.is_air(), children.iter().all(|c| c.is_air()));
            }
        }}}
        // No all-air coarse chunk is stored.
        for (_, c) in coarse.iter() {
            prop_assert!(c.non_air_count() > 0);
        }
    }
}

#[test]
fn an_unknown_id_is_an_error_naming_it() {
    let classes = BlockClasses::from_palette(&palette());
    let mut world: WorldMap = WorldMap::new(ChunkSize::S16);
    world.set_block(WorldPos::new(3, 4, 5), BlockId(77));
    let err = downsample_world(&world, &classes).unwrap_err();
    assert!(
        matches!(
            err,
            mesher::MeshError::UnknownBlock {
                id: BlockId(77),
                ..
            }
        ),
        "{err:?}"
    );
}
