//! Clutter placement: determinism, independence from the chunk split, density (zero, scaling,
//! rejection of invalid values), and every unit on a clutter-bearing top face with air above.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod surface_blocks_support;

use std::collections::BTreeMap;

use glam::Vec3;
use mesher::{
    BlockClasses, ClutterLayer, ClutterParams, InvalidClutterDensity, MeshError, clutter_extent,
    clutter_hash, place_clutter,
};
use proptest::prelude::*;
use surface_blocks_support::*;
use voxel_core::formats::{ClutterUnit, ClutterUnitFields};
use voxel_core::storage::{DenseChunk, WorldMap};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, LocalPos, MaterialClass, PaddedChunk, WorldPos,
    gather_neighbourhood,
};

fn params(density: f32, seed: u64) -> ClutterParams {
    ClutterParams::new(density, seed).unwrap()
}

fn density() -> impl Strategy<Value = f32> {
    prop_oneof![Just(1.0f32), Just(8.0), 0.0f32..=8.0]
}

fn is_clutter_bearing(id: BlockId) -> bool {
    palette().class(id) == Ok(MaterialClass::ClutterBearing)
}

/// A world of hills: grass and moss tops, stone below, water in the hollows, some floating
/// blocks (so that tops under stone and under water occur), from a seed.
fn world_block(seed: u64, p: [i32; 3]) -> BlockId {
    let h = |x: i32, z: i32| {
        let mut r = Rng(seed ^ (x as u64).wrapping_mul(0x1000_0000_01B3) ^ (z as u64) << 32);
        (r.below(6) as i32) - 3 + (x / 7) - (z / 9)
    };
    let ground = h(p[0], p[2]);
    let mut r = Rng(seed ^ clutter_hash(p.map(i64::from), 99));
    if p[1] < ground {
        if r.below(8) == 0 { DIRT } else { STONE }
    } else if p[1] == ground {
        if r.below(3) == 0 { MOSS } else { GRASS }
    } else if p[1] <= -2 {
        WATER
    } else if r.below(40) == 0 {
        [STONE, GRASS, GLASS][r.below(3) as usize]
    } else {
        BlockId::AIR
    }
}

/// Chunks of `size` covering world `[-32, 32)^3`, filled from [`world_block`].
fn world(size: ChunkSize, seed: u64) -> WorldMap<DenseChunk> {
    let mut map = WorldMap::new(size);
    let e = size.edge() as i32;
    let n = 64 / e;
    for cz in -n / 2..n / 2 {
        for cy in -n / 2..n / 2 {
            for cx in -n / 2..n / 2 {
                let coord = ChunkCoord::new(cx, cy, cz);
                let chunk = DenseChunk::from_fn(size, |l: LocalPos| {
                    let w = coord.world_pos(l, size).unwrap();
                    world_block(seed, [w.x, w.y, w.z])
                });
                map.insert(coord, chunk).unwrap();
            }
        }
    }
    map
}

/// Every unit of every chunk of `world`, decoded, with its world position.
fn world_units(
    world: &WorldMap<DenseChunk>,
    params: &ClutterParams,
) -> Vec<(Vec3, ClutterUnitFields)> {
    let classes = BlockClasses::from_palette(&palette());
    let size = world.size();
    let mut coords: Vec<ChunkCoord> = world.iter().map(|(c, _)| c).collect();
    coords.sort();
    let mut padded = PaddedChunk::new(size);
    let mut layer = ClutterLayer::new();
    let mut out = Vec::new();
    for coord in coords {
        gather_neighbourhood(world, coord, &mut padded);
        place_clutter(&padded, &classes, coord, params, &mut layer).unwrap();
        let origin = coord.origin(size).unwrap();
        let origin = Vec3::new(origin.x as f32, origin.y as f32, origin.z as f32);
        for unit in layer.units() {
            let fields = unit.decode(clutter_extent(size));
            out.push((origin + fields.position, fields));
        }
    }
    out
}

/// The settings, uv and tint of a unit: everything but position and normal, bit for bit.
fn key(f: &ClutterUnitFields) -> (u8, u8, u8, [u32; 2], [u32; 2], [u8; 4]) {
    (
        f.kind,
        f.scale_step,
        f.seed,
        f.uv.to_array().map(f32::to_bits),
        f.uv_size.to_array().map(f32::to_bits),
        f.tint,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn same_world_same_clutter_whatever_the_chunk_size(
        world_seed in any::<u64>(),
        seed in any::<u64>(),
        density in density(),
    ) {
        let params = params(density, seed);
        let small = world_units(&world(ChunkSize::S16, world_seed), &params);
        let large = world_units(&world(ChunkSize::S32, world_seed), &params);
        // The hills have about 4,000 grass and moss tops with air above.
        prop_assert!(small.len() as f32 >= density * 2000.0 - 500.0, "{} units", small.len());
        prop_assert_eq!(small.len(), large.len());
        // Match units with equal settings whose world positions agree within the two
        // quantization bounds.
        let tolerance = clutter_extent(ChunkSize::S16).max_error()
            + clutter_extent(ChunkSize::S32).max_error()
            + 1e-5;
        let mut pool: BTreeMap<_, Vec<Vec3>> = BTreeMap::new();
        for (pos, f) in &large {
            pool.entry(key(f)).or_default().push(*pos);
        }
        for (pos, f) in &small {
            let candidates = pool.get_mut(&key(f));
            prop_assert!(candidates.is_some(), "no unit like {:?} in the 32^3 split", f);
            let candidates = candidates.unwrap();
            let found = candidates
                .iter()
                .position(|q| (*q - *pos).abs().max_element() <= tolerance);
            prop_assert!(found.is_some(), "{:?} at {} has no twin in the 32^3 split", f, pos);
            candidates.swap_remove(found.unwrap());
        }
    }

}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn every_unit_stands_on_a_clutter_bearing_top_face_with_air_above(
        spec in chunk_spec(),
        coord in any::<[i32; 3]>(),
        seed in any::<u64>(),
        density in density(),
    ) {
        let classes = BlockClasses::from_palette(&palette());
        let chunk = spec.build();
        let coord = ChunkCoord::new(coord[0], coord[1], coord[2]);
        let params = params(density, seed);
        let mut out = ClutterLayer::new();
        place_clutter(&chunk, &classes, coord, &params, &mut out).unwrap();
        let extent = clutter_extent(spec.size);
        let bound = extent.max_error();
        let mut per_face: BTreeMap<[u32; 3], u32> = BTreeMap::new();
        for unit in out.units() {
            let f = unit.decode(extent);
            let p = f.position;
            let top = p.y.round();
            prop_assert!((p.y - top).abs() <= bound, "{} is not on a face", p);
            prop_assert!(top >= 1.0);
            // Offsets keep 1/32 voxel from the edges: floor gives the block.
            for v in [p.x, p.z] {
                let inside = (1.0 / 32.0 - bound..=31.0 / 32.0 + bound).contains(&v.fract());
                prop_assert!(inside, "{} is too close to a block edge", p);
            }
            let face = [p.x.floor() as u32, top as u32 - 1, p.z.floor() as u32];
            prop_assert!(face.iter().all(|&a| a < spec.size.edge()), "{} outside", p);
            let id = id_at(&chunk, face);
            let above = chunk.get(face[0] + 1, face[1] + 2, face[2] + 1).unwrap();
            prop_assert!(
                is_clutter_bearing(id) && above.is_air(),
                "{:?} on {:?} ({:?} under {:?})", f, face, id, above
            );
            prop_assert_eq!(u32::from(f.kind) >> 2, u32::from(id.0 & 63));
            *per_face.entry(face).or_default() += 1;
            prop_assert_eq!(f.normal, Vec3::Y);
            let (col, row) = (f32::from(f.kind % 16) / 16.0, f32::from(f.kind / 16) / 16.0);
            prop_assert!((f.uv.x - col).abs() <= 1e-4 && (f.uv.y - row).abs() <= 1e-4, "{:?}", f);
            prop_assert_eq!(unit.uv_size, [15, 15]);
            prop_assert_eq!(f.tint[3], 255);
            prop_assert!(f.tint[..3].iter().all(|&c| c >= 224));
        }
        // Every clutter-bearing top with air above holds floor(density) or floor(density) + 1
        // units (only those faces hold any, as checked above).
        let whole = density.floor() as u32;
        for pos in positions(spec.size) {
            let above = chunk.get(pos[0] + 1, pos[1] + 2, pos[2] + 1).unwrap();
            if is_clutter_bearing(id_at(&chunk, pos)) && above.is_air() {
                let count = per_face.get(&pos).copied().unwrap_or(0);
                prop_assert!(count == whole || count == whole + 1, "{:?}: {} units", pos, count);
            }
        }
    }

    #[test]
    fn same_input_twice_gives_identical_units(
        spec in chunk_spec(),
        coord in any::<[i32; 3]>(),
        seed in any::<u64>(),
        density in density(),
    ) {
        let classes = BlockClasses::from_palette(&palette());
        let chunk = spec.build();
        let coord = ChunkCoord::new(coord[0], coord[1], coord[2]);
        let params = params(density, seed);
        let mut a = ClutterLayer::new();
        let mut b = ClutterLayer::new();
        place_clutter(&chunk, &classes, coord, &params, &mut a).unwrap();
        place_clutter(&spec.build(), &classes, coord, &params, &mut b).unwrap();
        prop_assert_eq!(a.units(), b.units());
        // Reusing the buffer changes nothing.
        place_clutter(&chunk, &classes, coord, &params, &mut a).unwrap();
        prop_assert_eq!(a.units(), b.units());
    }
}

/// `chunks` S62 chunks with a flat floor of grass at y = 0 and air above.
fn meadow_units(density: f32, seed: u64, chunks: i32) -> (usize, Vec<ClutterUnit>) {
    let classes = BlockClasses::from_palette(&palette());
    let chunk = PaddedChunk::from_fn(
        ChunkSize::S62,
        |_, y, _| if y <= 1 { GRASS } else { BlockId::AIR },
    );
    let mut out = ClutterLayer::new();
    let mut units = Vec::new();
    for i in 0..chunks {
        place_clutter(
            &chunk,
            &classes,
            ChunkCoord::new(i, -i, 3 * i),
            &params(density, seed),
            &mut out,
        )
        .unwrap();
        units.extend_from_slice(out.units());
    }
    (62 * 62 * chunks as usize, units)
}

#[test]
fn density_zero_places_nothing() {
    for seed in [0, 1, u64::MAX] {
        assert!(meadow_units(0.0, seed, 1).1.is_empty());
    }
    assert!(meadow_units(-0.0, 5, 1).1.is_empty());
}

#[test]
fn the_mean_count_per_face_follows_the_density() {
    // 4 chunks of 62^3: 15,376 faces. The count per face is floor(d) or floor(d) + 1, so its
    // standard deviation is at most 0.5 and that of the mean at most 0.5 / sqrt(15376) = 0.004;
    // the bound 0.03 is more than 7 standard deviations.
    for density in [0.05f32, 0.25, 0.5, 1.0, 1.3, 2.75, 4.5, 7.9, 8.0] {
        let (faces, units) = meadow_units(density, 12345, 4);
        let mean = units.len() as f64 / faces as f64;
        assert!(
            (mean - f64::from(density)).abs() <= 0.03,
            "density {density}: {mean} units per face"
        );
    }
    // Offsets spread over the face, variants and settings all occur.
    let (_, units) = meadow_units(2.0, 99, 1);
    let extent = clutter_extent(ChunkSize::S62);
    let mut mean = [0.0f64; 2];
    let mut variants = [0usize; 4];
    let mut scales = [0usize; 16];
    for unit in &units {
        let f = unit.decode(extent);
        mean[0] += f64::from(f.position.x.fract());
        mean[1] += f64::from(f.position.z.fract());
        variants[usize::from(f.kind & 3)] += 1;
        scales[usize::from(f.scale_step)] += 1;
    }
    let n = units.len() as f64;
    assert!(mean.iter().all(|m| (m / n - 0.5).abs() < 0.02), "{mean:?}");
    assert!(
        variants.iter().all(|&v| v as f64 > n / 4.0 * 0.8),
        "{variants:?}"
    );
    assert!(
        scales.iter().all(|&v| v as f64 > n / 16.0 * 0.7),
        "{scales:?}"
    );
}

#[test]
fn invalid_densities_are_errors_not_clamped() {
    for bad in [
        f32::NAN,
        -f32::NAN,
        -0.001,
        -1.0,
        8.001,
        9.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ] {
        let err = ClutterParams::new(bad, 0).unwrap_err();
        assert!(err.value.to_bits() == bad.to_bits(), "{bad}");
        assert!(err.to_string().contains("0.0..=8"), "{err}");
    }
    assert_eq!(
        ClutterParams::new(8.5, 0),
        Err(InvalidClutterDensity { value: 8.5 })
    );
    for good in [0.0, 0.5, 8.0] {
        assert_eq!(ClutterParams::new(good, 3).unwrap().density(), good);
    }
}

#[test]
fn unknown_ids_with_air_above_are_errors() {
    let classes = BlockClasses::from_palette(&palette());
    let chunk = PaddedChunk::from_fn(ChunkSize::S16, |x, y, z| match (x, y, z) {
        (5, 1, 7) => UNKNOWN,
        (_, 1, _) => GRASS,
        _ => BlockId::AIR,
    });
    let mut out = ClutterLayer::new();
    place_clutter(
        &chunk,
        &classes,
        ChunkCoord::default(),
        &params(1.0, 0),
        &mut out,
    )
    .unwrap_err();
    assert_eq!(
        place_clutter(
            &chunk,
            &classes,
            ChunkCoord::default(),
            &params(1.0, 0),
            &mut out
        ),
        Err(MeshError::UnknownBlock {
            id: UNKNOWN,
            position: [5, 1, 7]
        })
    );
    assert!(out.is_empty());
    // Buried under stone, the unknown id is never read.
    let covered = PaddedChunk::from_fn(ChunkSize::S16, |x, y, z| match (x, y, z) {
        (5, 1, 7) => UNKNOWN,
        (5, 2, 7) => STONE,
        (_, 1, _) => GRASS,
        _ => BlockId::AIR,
    });
    place_clutter(
        &covered,
        &classes,
        ChunkCoord::default(),
        &params(1.0, 0),
        &mut out,
    )
    .unwrap();
    assert_eq!(out.len(), 16 * 16 - 1);
}

#[test]
fn the_hash_is_the_documented_splitmix_chain() {
    fn splitmix(x: u64) -> u64 {
        let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    for (w, seed) in [
        ([0i64, 0, 0], 0u64),
        ([-1, 5, i64::from(i32::MIN)], 77),
        ([3, -9, 2], u64::MAX),
    ] {
        let expected =
            splitmix(splitmix(splitmix(splitmix(seed) ^ w[0] as u64) ^ w[1] as u64) ^ w[2] as u64);
        assert_eq!(clutter_hash(w, seed), expected);
    }
    // The clutter of a block is a function of its world position: the same grass block in
    // chunk (0, 2, 0) of an 8^3 world and chunk (0, 0, 0) of a 32^3 world.
    let at = WorldPos::new(3, 17, 5);
    let classes = BlockClasses::from_palette(&palette());
    let mut decoded = Vec::new();
    for size in [ChunkSize::S8, ChunkSize::S32] {
        let (coord, local) = at.split(size);
        let chunk = PaddedChunk::from_fn(size, |x, y, z| {
            if [x, y, z] == [local.x, local.y, local.z].map(|a| u32::from(a) + 1) {
                GRASS
            } else {
                BlockId::AIR
            }
        });
        let mut out = ClutterLayer::new();
        place_clutter(&chunk, &classes, coord, &params(3.0, 8), &mut out).unwrap();
        assert_eq!(out.len(), 3);
        let origin = coord.origin(size).unwrap();
        let origin = Vec3::new(origin.x as f32, origin.y as f32, origin.z as f32);
        decoded.push(
            out.units()
                .iter()
                .map(|u| {
                    (
                        origin + u.decode(clutter_extent(size)).position,
                        u.settings,
                        u.tint,
                    )
                })
                .collect::<Vec<_>>(),
        );
    }
    for (a, b) in decoded[0].iter().zip(&decoded[1]) {
        assert!((a.0 - b.0).abs().max_element() < 2e-3, "{a:?} {b:?}");
        assert_eq!((a.1, a.2), (b.1, b.2));
    }
}
