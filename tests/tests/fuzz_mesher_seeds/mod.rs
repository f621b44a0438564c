//! The seed inputs of the fuzz targets in `fuzz/mesher_bodies/` (`vertical_shells`,
//! `surface_blocks`, `place_clutter`, `lod`): every chunk size and fill layout, palettes of
//! every class (more than 8 transparent ids, emissive entries), unknown and large ids, and the
//! extreme parameters (densities around the valid range, NaN, chunk coordinates at the ends of
//! `i32`).

use super::Seeds;

/// A chunk input: chunk `edge` (8, 16, 32 or 62), `fill` 0..4 (voxels, 2^3 cells, 4^3 cells,
/// columns), `classes` of the palette entries (2 bits each: opaque, transparent, clutter-bearing,
/// smoothable), `emissive` bits, then `voxels`.
fn chunk(edge: u8, fill: u8, entries: u8, classes: u32, emissive: u16, voxels: &[u8]) -> Vec<u8> {
    let size = match edge {
        8 => 0,
        16 => 4,
        32 => 6,
        62 => 7,
        _ => panic!("no chunk edge {edge}"),
    };
    let mut bytes = vec![size | fill << 3, entries];
    bytes.extend_from_slice(&classes.to_le_bytes());
    bytes.extend_from_slice(&emissive.to_le_bytes());
    bytes.extend_from_slice(voxels);
    bytes
}

/// Every class in turn: entries 1..=15 are opaque, transparent, clutter-bearing, smoothable, ...
const MIXED: u32 = 0b11_10_01_00_11_10_01_00_11_10_01_00_11_10_01_00;
/// Entries 1..=15 all transparent (past the 8 ids compared row by row).
const ALL_TRANSPARENT: u32 = 0x5555_5555;
/// Entries 1..=15 all clutter-bearing.
const ALL_CLUTTER: u32 = 0xAAAA_AAAA;

/// Terrain columns: height, body id, top id (ids 1..=15 of the [`MIXED`] palette).
fn terrain() -> Vec<u8> {
    (0..97u8)
        .flat_map(|i| [3 + i % 9, 2 + i % 2, 3 + 4 * (i % 3)])
        .collect()
}

/// The inputs of `vertical_shells` and `surface_blocks`.
pub(crate) fn chunk_seeds() -> Seeds {
    let ramp: Vec<u8> = (0..=255u8).collect();
    vec![
        ("empty-8", chunk(8, 0, 0, 0, 0, &[])),
        ("stone-full-16", chunk(16, 0, 1, 0, 0, &[1])),
        ("checker-8", chunk(8, 0, 2, MIXED, 0, &[1, 0])),
        ("ramp-mixed-16", chunk(16, 0, 15, MIXED, 0x5A5A, &ramp)),
        (
            "cells2-transparent-32",
            chunk(32, 1, 15, ALL_TRANSPARENT, 0, &ramp[..40]),
        ),
        (
            "cells4-mixed-62",
            chunk(62, 2, 15, MIXED, 0xFFFF, &ramp[..64]),
        ),
        ("terrain-16", chunk(16, 3, 15, MIXED, 0x0F0F, &terrain())),
        ("terrain-62", chunk(62, 3, 15, MIXED, 0, &terrain())),
        (
            "unknown-ids-8",
            chunk(8, 1, 3, MIXED, 0, &[0, 16, 0xF0, 0, 0xFF, 2, 17, 0]),
        ),
        (
            "water-glass-8",
            chunk(8, 1, 2, ALL_TRANSPARENT, 1, &[1, 2, 0, 1, 1, 2]),
        ),
        ("short-header", vec![7, 15, 0, 0]),
    ]
}

/// Clutter parameters: density, seed, chunk coordinate.
fn clutter_params(density: f32, seed: u64, coord: [i32; 3]) -> Vec<u8> {
    let mut bytes = density.to_le_bytes().to_vec();
    bytes.extend_from_slice(&seed.to_le_bytes());
    for c in coord {
        bytes.extend_from_slice(&c.to_le_bytes());
    }
    bytes
}

/// The inputs of `place_clutter`.
pub(crate) fn clutter_seeds() -> Seeds {
    let grass_floor = chunk(16, 3, 15, ALL_CLUTTER, 0, &[2, 1, 3]);
    let with = |density: f32, seed: u64, coord: [i32; 3], input: &[u8]| {
        let mut bytes = clutter_params(density, seed, coord);
        bytes.extend_from_slice(input);
        bytes
    };
    vec![
        ("floor-2-16", with(2.0, 7, [0, 0, 0], &grass_floor)),
        ("floor-fraction", with(0.37, 1, [-1, 2, -3], &grass_floor)),
        (
            "floor-max-far",
            with(8.0, u64::MAX, [i32::MAX; 3], &grass_floor),
        ),
        ("floor-min-coord", with(1.5, 0, [i32::MIN; 3], &grass_floor)),
        ("zero-density", with(0.0, 3, [0, 0, 0], &grass_floor)),
        ("negative-zero", with(-0.0, 3, [0, 0, 0], &grass_floor)),
        ("too-dense", with(8.000_001, 3, [0, 0, 0], &grass_floor)),
        ("nan", with(f32::NAN, 3, [0, 0, 0], &grass_floor)),
        ("infinite", with(f32::INFINITY, 3, [0, 0, 0], &grass_floor)),
        ("negative", with(-1.0, 3, [0, 0, 0], &grass_floor)),
        (
            "terrain-62",
            with(1.0, 9, [5, -6, 7], &chunk(62, 3, 15, MIXED, 0, &terrain())),
        ),
        (
            "unknown-top",
            with(
                1.0,
                9,
                [0, 0, 0],
                &chunk(8, 3, 3, ALL_CLUTTER, 0, &[4, 1, 16]),
            ),
        ),
        ("short", clutter_params(1.0, 0, [0, 0, 0])),
    ]
}

/// LOD parameters: sides at the same level, a finer chunk of another size, which finer chunks
/// exist, the base chunk coordinate.
fn lod_params(same_level: u8, mismatched: bool, present: u8, base: [i32; 3]) -> Vec<u8> {
    let mut bytes = vec![same_level | u8::from(mismatched) << 6, present];
    for c in base {
        bytes.extend_from_slice(&c.to_le_bytes());
    }
    bytes
}

/// The inputs of `lod`.
pub(crate) fn lod_seeds() -> Seeds {
    let with = |params: Vec<u8>, input: &[u8]| {
        let mut bytes = params;
        bytes.extend_from_slice(input);
        bytes
    };
    let mixed = chunk(8, 0, 15, MIXED, 0, &(0..=200u8).collect::<Vec<_>>());
    let terrain = chunk(16, 3, 15, MIXED, 0, &terrain());
    vec![
        ("all-8", with(lod_params(0, false, 0xFF, [0, 0, 0]), &mixed)),
        (
            "some-odd-base",
            with(
                lod_params(0b10_1010, false, 0b1011_0110, [-3, 5, -7]),
                &mixed,
            ),
        ),
        (
            "terrain-16-max",
            with(lod_params(0b11_0011, false, 0xFF, [i32::MAX; 3]), &terrain),
        ),
        (
            "terrain-16-min",
            with(lod_params(0x3F, false, 0x0F, [i32::MIN; 3]), &terrain),
        ),
        (
            "mismatched",
            with(lod_params(0, true, 0xFF, [0, 0, 0]), &mixed),
        ),
        ("none", with(lod_params(0, false, 0, [1, 1, 1]), &mixed)),
        (
            "unknown",
            with(
                lod_params(1, false, 0x81, [2, 0, 0]),
                &chunk(8, 1, 2, MIXED, 0, &[0, 16, 1]),
            ),
        ),
        ("short", lod_params(0, false, 0xFF, [0, 0, 0])),
    ]
}
