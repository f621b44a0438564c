//! Whole regions of the terrain as chunk maps: a grid of chunks ([`terrain_scene`]) or an exact
//! square of block columns ([`terrain_columns`]).

use rayon::prelude::*;
use voxel_core::storage::{DenseChunk, PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos, MaterialPalette};

use super::{Terrain, TerrainBlocks};

/// Height above which the terrain is always air: `base_height + amplitude` of
/// [`Terrain::new`] rounded up with margin (the sea is lower).
pub const TERRAIN_TOP: i32 = 40;

/// A generated region of the terrain: its chunks, the materials their ids index, and the
/// generator (for heights, e.g. to place a camera).
#[derive(Debug)]
pub struct TerrainScene {
    /// The voxels, palette-compressed per chunk; all-air chunks are not stored.
    pub world: WorldMap<PaletteChunk>,
    /// The materials of the ids in `world` ([`TerrainBlocks::palette`]).
    pub palette: MaterialPalette,
    /// The generator that made `world`.
    pub terrain: Terrain,
}

/// Generates the terrain of `seed` over `chunks_x * chunks_z` chunk columns of `size`, centred
/// on the origin (chunk x from `-chunks_x / 2`), `chunks_y` chunks tall from y = 0. Chunks are
/// generated in parallel on rayon's current pool.
pub fn terrain_scene(
    seed: i32,
    size: ChunkSize,
    chunks_x: i32,
    chunks_y: i32,
    chunks_z: i32,
) -> TerrainScene {
    let coords: Vec<ChunkCoord> = (-chunks_z / 2..chunks_z - chunks_z / 2)
        .flat_map(|z| {
            (0..chunks_y).flat_map(move |y| {
                (-chunks_x / 2..chunks_x - chunks_x / 2).map(move |x| ChunkCoord::new(x, y, z))
            })
        })
        .collect();
    generate(seed, size, &coords, |_, _| true)
}

/// Generates the terrain of `seed` over exactly `side x side` block columns, x and z in
/// `-side / 2 .. side - side / 2`, from y = 0 up to [`TERRAIN_TOP`], in chunks of `size`. The
/// blocks do not depend on `size`: only how they are split into chunks does.
pub fn terrain_columns(seed: i32, size: ChunkSize, side: u32) -> TerrainScene {
    let side = i64::from(side);
    let lo = -side / 2;
    let hi = side - side / 2; // exclusive
    let edge = i64::from(size.edge());
    let chunk_range = |lo: i64, hi: i64| lo.div_euclid(edge)..=(hi - 1).div_euclid(edge);
    let ys = 0..=(i64::from(TERRAIN_TOP)).div_euclid(edge);
    let mut coords = Vec::new();
    if side > 0 {
        for z in chunk_range(lo, hi) {
            for y in ys.clone() {
                for x in chunk_range(lo, hi) {
                    coords.push(ChunkCoord::new(x as i32, y as i32, z as i32));
                }
            }
        }
    }
    let inside =
        move |x: i32, z: i32| (lo..hi).contains(&i64::from(x)) && (lo..hi).contains(&i64::from(z));
    generate(seed, size, &coords, inside)
}

/// Generates the chunks `coords`, keeping only the columns where `column(x, z)` holds.
fn generate(
    seed: i32,
    size: ChunkSize,
    coords: &[ChunkCoord],
    column: impl Fn(i32, i32) -> bool + Sync,
) -> TerrainScene {
    let (palette, blocks) = TerrainBlocks::palette();
    let terrain = Terrain::new(seed, blocks);
    let edge = size.edge() as i32;
    let chunks: Vec<(ChunkCoord, PaletteChunk)> = coords
        .par_iter()
        .filter_map(|&coord| {
            let mut dense = DenseChunk::new(size);
            let (x0, y0, z0) = (coord.x * edge, coord.y * edge, coord.z * edge);
            for lz in 0..edge {
                for lx in 0..edge {
                    if !column(x0 + lx, z0 + lz) {
                        continue;
                    }
                    let ground = terrain.height(x0 + lx, z0 + lz);
                    for ly in 0..edge {
                        if y0 + ly > TERRAIN_TOP {
                            break;
                        }
                        let id = terrain.block_in_column(x0 + lx, y0 + ly, z0 + lz, ground);
                        if id != BlockId::AIR {
                            let local = LocalPos::new(lx as u32, ly as u32, lz as u32, size)
                                .expect("loop bounds are inside the chunk");
                            dense.set(local, id).expect("local position checked above");
                        }
                    }
                }
            }
            (dense.non_air_count() > 0).then(|| (coord, PaletteChunk::from_dense(&dense)))
        })
        .collect();
    let mut world = WorldMap::new(size);
    for (coord, chunk) in chunks {
        world
            .insert(coord, chunk)
            .expect("every chunk was made with the world's size");
    }
    TerrainScene {
        world,
        palette,
        terrain,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blocks(scene: &TerrainScene) -> Vec<(i32, i32, i32, u16)> {
        let size = scene.world.size();
        let mut out: Vec<(i32, i32, i32, u16)> = scene
            .world
            .iter()
            .flat_map(|(coord, chunk)| {
                chunk
                    .iter()
                    .filter(|(_, id)| !id.is_air())
                    .map(move |(local, id)| {
                        let p = coord.world_pos(local, size).expect("in the i32 world");
                        (p.x, p.y, p.z, id.0)
                    })
            })
            .collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn columns_are_exact_and_do_not_depend_on_the_chunk_size() {
        let a = terrain_columns(5, ChunkSize::S16, 37);
        let b = terrain_columns(5, ChunkSize::S32, 37);
        let (va, vb) = (blocks(&a), blocks(&b));
        assert_eq!(va, vb);
        let xs = va.iter().map(|v| v.0);
        let zs = va.iter().map(|v| v.2);
        assert_eq!((xs.clone().min(), xs.max()), (Some(-18), Some(18)));
        assert_eq!((zs.clone().min(), zs.max()), (Some(-18), Some(18)));
        // Every column of the square holds its ground block, read back from the generator.
        for x in -18..=18 {
            for z in -18..=18 {
                let ground = a.terrain.height(x, z);
                let id = a.terrain.block_at(x, ground, z);
                if !id.is_air() {
                    assert!(va.binary_search(&(x, ground, z, id.0)).is_ok());
                }
            }
        }
        assert!(terrain_columns(5, ChunkSize::S16, 0).world.is_empty());
    }

    #[test]
    fn the_chunk_grid_matches_the_generator() {
        let scene = terrain_scene(3, ChunkSize::S16, 2, 3, 2);
        for (x, y, z, id) in blocks(&scene) {
            assert!((-16..16).contains(&x) && (0..48).contains(&y) && (-16..16).contains(&z));
            assert_eq!(scene.terrain.block_at(x, y, z).0, id);
        }
    }
}
