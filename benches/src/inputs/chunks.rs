//! Chunk inputs: terrain with caves from the procedural generator, a 3 x 3 x 3 world around it,
//! uniform chunks, random chunks with a chosen number of ids, and random positions.
//!
//! The terrain is [`voxel_scene::Terrain`] with seed [`TERRAIN_SEED`]: rolling hills around
//! y = 18 (amplitude 14), a sea up to y = 14, 3-D noise caves from y = 1 up to 3 blocks below
//! the ground, and 7 ids in all (air, grass, dirt, stone, sand, water, snow). Chunk
//! [`TERRAIN_CENTRE`] at y = 0 holds the surface for every chunk size, so its voxels mix air,
//! water, surface layers, stone and caves; at 32^3 and 62^3 the chunks below it are solid stone
//! and the chunks above it are air, as in a real world.

use voxel_core::storage::{DenseChunk, PaletteChunk, WorldMap};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos};
use voxel_scene::{Terrain, TerrainBlocks};

use crate::rng::Rng;

/// The seed of every terrain input.
pub const TERRAIN_SEED: i32 = 7;

/// The chunk coordinate of the terrain chunk the benches use: it crosses the surface, contains
/// caves and uses all 7 ids at 32^3 and at 62^3 (4 bits per voxel in palette form).
pub const TERRAIN_CENTRE: ChunkCoord = ChunkCoord::new(-1, 0, 2);

/// The id of [`uniform_chunk`]: the terrain's stone.
pub fn stone() -> BlockId {
    TerrainBlocks::palette().1.stone
}

/// The generator behind every terrain input.
pub fn terrain() -> Terrain {
    Terrain::new(TERRAIN_SEED, TerrainBlocks::palette().1)
}

/// The terrain chunk at `coord`, generated column by column.
pub fn terrain_chunk(size: ChunkSize, coord: ChunkCoord) -> DenseChunk {
    terrain_chunk_with(&terrain(), size, coord)
}

fn terrain_chunk_with(terrain: &Terrain, size: ChunkSize, coord: ChunkCoord) -> DenseChunk {
    let e = size.edge() as i32;
    let [x0, y0, z0] = [coord.x * e, coord.y * e, coord.z * e];
    let ground: Vec<i32> = (0..e * e)
        .map(|i| terrain.height(x0 + i % e, z0 + i / e))
        .collect();
    DenseChunk::from_fn(size, |p: LocalPos| {
        let (x, y, z) = (i32::from(p.x), i32::from(p.y), i32::from(p.z));
        let g = ground[(x + e * z) as usize];
        terrain.block_in_column(x0 + x, y0 + y, z0 + z, g)
    })
}

/// [`TERRAIN_CENTRE`] at `size`: the terrain chunk the storage, gather and codec benches use.
pub fn terrain_centre(size: ChunkSize) -> DenseChunk {
    terrain_chunk(size, TERRAIN_CENTRE)
}

/// The 27 terrain chunks [`TERRAIN_CENTRE`] and its 26 neighbours, each turned into the
/// world's chunk type by `convert`. Every chunk is stored, even the all-stone and all-air ones,
/// so a gather around the centre reads 27 real chunks and never the "missing chunk" path.
pub fn terrain_world<C: voxel_core::storage::VoxelStorage>(
    size: ChunkSize,
    convert: impl Fn(DenseChunk) -> C,
) -> WorldMap<C> {
    let c = TERRAIN_CENTRE;
    terrain_world_between(
        size,
        [c.x - 1, c.y - 1, c.z - 1],
        [c.x + 1, c.y + 1, c.z + 1],
        convert,
    )
}

/// Every terrain chunk whose chunk coordinates lie between `low` and `high` (both included),
/// each turned into the world's chunk type by `convert`, from one generator.
pub fn terrain_world_between<C: voxel_core::storage::VoxelStorage>(
    size: ChunkSize,
    low: [i32; 3],
    high: [i32; 3],
    convert: impl Fn(DenseChunk) -> C,
) -> WorldMap<C> {
    let terrain = terrain();
    let mut world = WorldMap::new(size);
    for z in low[2]..=high[2] {
        for y in low[1]..=high[1] {
            for x in low[0]..=high[0] {
                let coord = ChunkCoord::new(x, y, z);
                let chunk = convert(terrain_chunk_with(&terrain, size, coord));
                world
                    .insert(coord, chunk)
                    .expect("the chunk has the world's size");
            }
        }
    }
    world
}

/// The height above which the terrain holds no solid block and no water: its highest hill
/// ([`Terrain::height`] reaches `base_height + amplitude`) or its sea, whichever is higher.
pub fn terrain_top() -> i32 {
    let t = terrain();
    (t.base_height + t.amplitude.ceil() as i32).max(t.sea_level)
}

/// [`terrain_world`] of [`DenseChunk`]s.
pub fn terrain_world_dense(size: ChunkSize) -> WorldMap<DenseChunk> {
    terrain_world(size, |c| c)
}

/// [`terrain_world`] of [`PaletteChunk`]s (each at its smallest width: the chunks below the
/// centre and above it are uniform).
pub fn terrain_world_palette(size: ChunkSize) -> WorldMap<PaletteChunk> {
    terrain_world(size, |c| PaletteChunk::from_dense(&c))
}

/// A chunk with every voxel set to [`stone`].
pub fn uniform_chunk(size: ChunkSize) -> DenseChunk {
    DenseChunk::filled(size, stone())
}

/// A chunk whose voxels are ids `0..ids` (0 is air) drawn uniformly at random: the worst case
/// for a palette of that many ids, with no runs to exploit. `ids` must be at least 1.
pub fn random_chunk(size: ChunkSize, ids: u16, seed: u64) -> DenseChunk {
    let mut rng = Rng::new(seed);
    let n = u64::from(ids.max(1));
    DenseChunk::from_fn(size, |_| BlockId(rng.below(n) as u16))
}

/// `n` uniformly random positions inside a chunk of `size`.
pub fn random_positions(size: ChunkSize, n: usize, seed: u64) -> Vec<LocalPos> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| rng.local(size)).collect()
}

/// `n` distinct random positions inside a chunk of `size` (`n` at most the volume), in random
/// order: a partial Fisher-Yates shuffle of the linear indices.
pub fn distinct_positions(size: ChunkSize, n: usize, seed: u64) -> Vec<LocalPos> {
    let volume = size.volume();
    assert!(
        n <= volume,
        "{n} distinct positions do not fit in {volume} voxels"
    );
    let mut rng = Rng::new(seed);
    let mut order: Vec<u32> = (0..volume as u32).collect();
    for i in 0..n {
        let j = i + rng.below((volume - i) as u64) as usize;
        order.swap(i, j);
    }
    let e = size.edge();
    order[..n]
        .iter()
        .map(|&i| LocalPos {
            x: (i % e) as u8,
            y: (i / e % e) as u8,
            z: (i / (e * e)) as u8,
        })
        .collect()
}

/// `n` ids drawn uniformly from `ids` (which must not be empty).
pub fn random_ids_from(ids: &[BlockId], n: usize, seed: u64) -> Vec<BlockId> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| ids[rng.below(ids.len() as u64) as usize])
        .collect()
}

/// One line describing a chunk as the benches see it: edge, distinct ids, non-air share and
/// the palette form (bits per voxel, heap bytes).
pub fn describe(name: &str, dense: &DenseChunk) -> String {
    use voxel_core::storage::VoxelStorage;
    let palette = PaletteChunk::from_dense(dense);
    let size = dense.size();
    format!(
        "{name}: {e}^3, {ids} ids, {solid:.1}% not air; palette form {bits} bits/voxel, \
         {heap} B heap (dense {dense_heap} B)",
        e = size.edge(),
        ids = palette.distinct_ids(),
        solid = 100.0 * dense.non_air_count() as f64 / size.volume() as f64,
        bits = palette.bits_per_voxel(),
        heap = palette.heap_bytes(),
        dense_heap = dense.heap_bytes(),
    )
}

#[cfg(test)]
mod tests {
    use voxel_core::storage::VoxelStorage;

    use super::*;

    /// Air voxels enclosed below the ground: a cave, not the sky or the sea.
    fn cave_voxels(dense: &DenseChunk, coord: ChunkCoord) -> usize {
        let t = terrain();
        let e = dense.size().edge() as i32;
        dense
            .iter()
            .filter(|(p, id)| {
                let (x, y, z) = (
                    coord.x * e + i32::from(p.x),
                    coord.y * e + i32::from(p.y),
                    coord.z * e + i32::from(p.z),
                );
                id.is_air() && y < t.height(x, z)
            })
            .count()
    }

    #[test]
    fn terrain_centre_has_surface_and_caves() {
        for size in [ChunkSize::S32, ChunkSize::S62] {
            let dense = terrain_centre(size);
            let volume = size.volume();
            let solid = dense.non_air_count();
            assert!(solid > volume / 10 && solid < volume * 9 / 10, "{solid}");
            let caves = cave_voxels(&dense, TERRAIN_CENTRE);
            assert!(caves > 100, "{size:?}: only {caves} cave voxels");
            let palette = PaletteChunk::from_dense(&dense);
            assert_eq!(palette.distinct_ids(), 7, "{}", describe("terrain", &dense));
            assert_eq!(palette.bits_per_voxel(), 4);
            assert_eq!(dense, terrain_centre(size), "deterministic");
        }
    }

    #[test]
    fn world_has_all_27_chunks() {
        let world = terrain_world_palette(ChunkSize::S32);
        assert_eq!(world.len(), 27);
        let below = TERRAIN_CENTRE.checked_offset([0, -1, 0]).unwrap();
        let above = TERRAIN_CENTRE.checked_offset([0, 1, 0]).unwrap();
        assert_eq!(world.get(below).and_then(|c| c.uniform()), Some(stone()));
        assert_eq!(
            world.get(above).and_then(|c| c.uniform()),
            Some(BlockId::AIR)
        );
    }

    #[test]
    fn distinct_positions_are_distinct() {
        let size = ChunkSize::S16;
        let mut p = distinct_positions(size, 1000, 3);
        assert!(p.iter().all(|q| q.check(size).is_ok()));
        p.sort_by_key(|q| (q.z, q.y, q.x));
        p.dedup();
        assert_eq!(p.len(), 1000);
    }

    #[test]
    fn random_chunk_uses_every_id() {
        let dense = random_chunk(ChunkSize::S32, 16, 1);
        assert_eq!(PaletteChunk::from_dense(&dense).distinct_ids(), 16);
        assert_eq!(PaletteChunk::from_dense(&dense).bits_per_voxel(), 4);
    }
}
