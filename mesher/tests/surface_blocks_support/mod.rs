//! Shared by the surface-block, shell and clutter tests: a palette with every material class,
//! random padded chunks, and a plain per-voxel reference of the visible-face rules.

use proptest::prelude::*;
use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, PaddedChunk};

/// The test palette's ids.
pub(crate) const STONE: BlockId = BlockId(1);
pub(crate) const DIRT: BlockId = BlockId(2);
pub(crate) const GRASS: BlockId = BlockId(3);
pub(crate) const SAND: BlockId = BlockId(4);
pub(crate) const LAMP: BlockId = BlockId(5);
pub(crate) const WATER: BlockId = BlockId(6);
pub(crate) const GLASS: BlockId = BlockId(7);
pub(crate) const GLOW_GLASS: BlockId = BlockId(8);
pub(crate) const MOSS: BlockId = BlockId(9);
pub(crate) const GLOW_SAND: BlockId = BlockId(10);
/// An id the palette does not know.
pub(crate) const UNKNOWN: BlockId = BlockId(500);

/// Every known non-air id of [`palette`].
pub(crate) const IDS: [BlockId; 10] = [
    STONE, DIRT, GRASS, SAND, LAMP, WATER, GLASS, GLOW_GLASS, MOSS, GLOW_SAND,
];

fn glowing(m: Material) -> Material {
    Material { emission: 200, ..m }
}

/// Air plus two opaque, two clutter-bearing (one emissive), two smoothable (one emissive), one
/// emissive opaque and three transparent (one emissive) materials.
pub(crate) fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    let add = |p: &mut MaterialPalette, m: Material| p.push(m).unwrap();
    assert_eq!(add(&mut p, Material::opaque(128, 128, 128)), STONE);
    assert_eq!(add(&mut p, Material::opaque(120, 80, 40)), DIRT);
    let grass = Material::opaque(40, 160, 40).with_class(MaterialClass::ClutterBearing);
    assert_eq!(add(&mut p, grass), GRASS);
    let sand = Material::opaque(220, 200, 120).with_class(MaterialClass::Smoothable);
    assert_eq!(add(&mut p, sand), SAND);
    assert_eq!(add(&mut p, glowing(Material::opaque(255, 240, 200))), LAMP);
    let water = Material::opaque(30, 60, 200).with_class(MaterialClass::Transparent);
    assert_eq!(add(&mut p, water), WATER);
    let glass = Material::opaque(200, 220, 230).with_class(MaterialClass::Transparent);
    assert_eq!(add(&mut p, glass), GLASS);
    assert_eq!(add(&mut p, glowing(glass)), GLOW_GLASS);
    let moss = Material::opaque(60, 120, 60).with_class(MaterialClass::ClutterBearing);
    assert_eq!(add(&mut p, glowing(moss)), MOSS);
    assert_eq!(add(&mut p, glowing(sand)), GLOW_SAND);
    p
}

/// A small deterministic generator for building test chunks from a proptest seed.
pub(crate) struct Rng(pub u64);

impl Rng {
    /// SplitMix64.
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n`.
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// How a random chunk is built.
#[derive(Clone, Debug)]
pub(crate) struct ChunkSpec {
    pub size: ChunkSize,
    pub seed: u64,
    /// Percent of cells that are not air.
    pub fill: u64,
    /// Edge of the cubes of equal id (1 = voxel noise; larger gives buried voxels, long runs
    /// and transparent ids next to equal ones).
    pub cell: u32,
    /// The ids drawn from, air aside.
    pub ids: Vec<BlockId>,
}

impl ChunkSpec {
    /// The padded chunk: every padded voxel (border included) drawn per `cell`^3 cube.
    pub(crate) fn build(&self) -> PaddedChunk {
        let p = self.size.padded_edge() as u32;
        let cells = p.div_ceil(self.cell) as usize;
        let mut rng = Rng(self.seed);
        let table: Vec<BlockId> = (0..cells * cells * cells)
            .map(|_| {
                if rng.below(100) < self.fill {
                    self.ids[rng.below(self.ids.len() as u64) as usize]
                } else {
                    BlockId::AIR
                }
            })
            .collect();
        let c = self.cell;
        PaddedChunk::from_fn(self.size, |x, y, z| {
            let (x, y, z) = ((x / c) as usize, (y / c) as usize, (z / c) as usize);
            table[x + cells * (y + cells * z)]
        })
    }
}

/// Every chunk size.
pub(crate) fn size() -> impl Strategy<Value = ChunkSize> {
    prop::sample::select(ChunkSize::ALL.to_vec())
}

/// Random chunks of every size: voxel noise and blocky cells, sparse to full, from all the
/// palette's ids or from subsets (opaque only, one transparent id with opaque ones).
pub(crate) fn chunk_spec() -> impl Strategy<Value = ChunkSpec> {
    let ids = prop_oneof![
        Just(IDS.to_vec()),
        Just(vec![STONE, GRASS, SAND]),
        Just(vec![WATER, STONE, GRASS]),
        Just(vec![WATER, GLASS]),
        prop::sample::subsequence(IDS.to_vec(), 1..=IDS.len()),
    ];
    (
        size(),
        any::<u64>(),
        prop_oneof![Just(100u64), 0u64..=100],
        prop_oneof![Just(1u32), 1u32..=6],
        ids,
    )
        .prop_map(|(size, seed, fill, cell, ids)| ChunkSpec {
            size,
            seed,
            fill,
            cell,
            ids,
        })
}

/// The face directions in `FaceDirection::ALL` order, as offsets.
pub(crate) const DIRS: [[i32; 3]; 6] = [
    [1, 0, 0],
    [-1, 0, 0],
    [0, 1, 0],
    [0, -1, 0],
    [0, 0, 1],
    [0, 0, -1],
];

/// Reference: which faces of chunk-local voxel `(x, y, z)` are visible, by the plain rules
/// (air shows nothing; a neighbour that is neither air nor transparent hides, unknown ids
/// included; a transparent voxel shows no face to an equal id).
pub(crate) fn faces_of(chunk: &PaddedChunk, palette: &MaterialPalette, pos: [u32; 3]) -> [bool; 6] {
    let at = |p: [i32; 3]| chunk.get(p[0] as u32, p[1] as u32, p[2] as u32).unwrap();
    let padded = pos.map(|a| a as i32 + 1);
    let id = at(padded);
    if id.is_air() {
        return [false; 6];
    }
    let transparent = |id: BlockId| palette.class(id) == Ok(MaterialClass::Transparent);
    DIRS.map(|d| {
        let n = at([padded[0] + d[0], padded[1] + d[1], padded[2] + d[2]]);
        let hides = !n.is_air() && !transparent(n);
        let same_transparent = transparent(id) && n == id;
        !hides && !same_transparent
    })
}

/// Every chunk-local position, z slowest.
pub(crate) fn positions(size: ChunkSize) -> impl Iterator<Item = [u32; 3]> {
    let e = size.edge();
    (0..e).flat_map(move |z| (0..e).flat_map(move |y| (0..e).map(move |x| [x, y, z])))
}

/// The chunk-local voxel's id.
pub(crate) fn id_at(chunk: &PaddedChunk, pos: [u32; 3]) -> BlockId {
    chunk.get(pos[0] + 1, pos[1] + 1, pos[2] + 1).unwrap()
}
