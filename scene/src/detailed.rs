//! Dense, detailed scenes for testing and benchmarking meshers, built voxel by voxel: a Menger
//! sponge (a fractal of many small holes, [`menger`]), a foliage scene (trees, leaves with
//! holes, grass blades, flowers: many thin, separate features of mixed ids, [`foliage`]) and a
//! flat maze (a floor and low walls of one id, a few voxels high and wide across many chunks,
//! [`flat_maze`]). All are deterministic.
//!
//! A [`VoxelBox`] is a box of ids with its palette; [`VoxelBox::padded_chunks`] cuts it into
//! padded chunks of any size, each gathered with its real neighbours, the way a world is
//! meshed.
//!
//! ```
//! use voxel_core::ChunkSize;
//! use voxel_scene::detailed::menger;
//!
//! let sponge = menger(2); // 9^3 voxels, 20^2 of them solid
//! assert_eq!(sponge.solid_voxels(), 400);
//! assert_eq!(sponge.padded_chunks(ChunkSize::S8).len(), 8);
//! ```

use voxel_core::storage::{DenseChunk, WorldMap};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos, Material, MaterialPalette};
use voxel_core::{PaddedChunk, gather_neighbourhood};

use crate::rng::Rng;

/// A box of voxels (x fastest, then y, then z) from the origin, and the palette of its ids.
#[derive(Clone, Debug)]
pub struct VoxelBox {
    /// Size along x, y and z.
    pub dims: [usize; 3],
    /// `dims[0] * dims[1] * dims[2]` ids, x fastest.
    pub ids: Vec<u16>,
    /// Materials of the ids.
    pub palette: MaterialPalette,
}

impl VoxelBox {
    /// An all-air scene of `dims`.
    fn new(dims: [usize; 3], palette: MaterialPalette) -> VoxelBox {
        VoxelBox {
            dims,
            ids: vec![0; dims[0] * dims[1] * dims[2]],
            palette,
        }
    }

    /// The id at `(x, y, z)`; air outside the box.
    pub fn get(&self, [x, y, z]: [i64; 3]) -> u16 {
        let [dx, dy, dz] = self.dims.map(|d| d as i64);
        if !(0..dx).contains(&x) || !(0..dy).contains(&y) || !(0..dz).contains(&z) {
            return 0;
        }
        self.ids[(x + dx * (y + dy * z)) as usize]
    }

    /// Sets `(x, y, z)` to `id`; positions outside the box are ignored.
    fn set(&mut self, [x, y, z]: [i64; 3], id: u16) {
        let [dx, dy, dz] = self.dims.map(|d| d as i64);
        if (0..dx).contains(&x) && (0..dy).contains(&y) && (0..dz).contains(&z) {
            self.ids[(x + dx * (y + dy * z)) as usize] = id;
        }
    }

    /// Voxels that are not air.
    pub fn solid_voxels(&self) -> usize {
        self.ids.iter().filter(|&&id| id != 0).count()
    }

    /// The box cut into chunks of `size`: every chunk with a solid voxel, in (z, y, x) order
    /// of chunk coordinates, each padded with its neighbours' voxels.
    pub fn padded_chunks(&self, size: ChunkSize) -> Vec<PaddedChunk> {
        let e = size.edge_usize();
        let counts = self.dims.map(|d| d.div_ceil(e));
        let mut world = WorldMap::new(size);
        let mut coords = Vec::new();
        for cz in 0..counts[2] {
            for cy in 0..counts[1] {
                for cx in 0..counts[0] {
                    let origin = [cx, cy, cz].map(|c| (c * e) as i64);
                    let chunk = DenseChunk::from_fn(size, |p: LocalPos| {
                        let local = [p.x, p.y, p.z].map(i64::from);
                        BlockId(self.get([0, 1, 2].map(|a| origin[a] + local[a])))
                    });
                    if chunk.as_slice().iter().all(|id| id.is_air()) {
                        continue;
                    }
                    let coord = ChunkCoord::new(cx as i32, cy as i32, cz as i32);
                    world
                        .insert(coord, chunk)
                        .expect("the chunk has the world's size");
                    coords.push(coord);
                }
            }
        }
        coords
            .into_iter()
            .map(|coord| {
                let mut padded = PaddedChunk::new(size);
                gather_neighbourhood(&world, coord, &mut padded);
                padded
            })
            .collect()
    }
}

/// True if `(x, y, z)`, each in `0..3^level`, is in the Menger sponge of `level`: no base-3
/// digit position has two or more of the coordinates' digits equal to 1 (the removed crosses).
pub fn in_menger_sponge(level: u32, [mut x, mut y, mut z]: [u64; 3]) -> bool {
    for _ in 0..level {
        let ones = u32::from(x % 3 == 1) + u32::from(y % 3 == 1) + u32::from(z % 3 == 1);
        if ones >= 2 {
            return false;
        }
        (x, y, z) = (x / 3, y / 3, z / 3);
    }
    true
}

/// The Menger sponge of `level` (edge `3^level`: 27, 81, 243 for levels 3, 4, 5) in stone, at
/// the origin.
pub fn menger(level: u32) -> VoxelBox {
    menger_with(level, &[Material::opaque(150, 150, 160)])
}

/// Edge of the blocks of [`menger_shaded`] that share a shade.
pub const SHADE_BLOCK: u64 = 9;

/// The Menger sponge of `level` (the holes of [`menger`]) in three shades of stone, one per
/// block of [`SHADE_BLOCK`]^3 voxels (the sum of the block's coordinates mod 3): the ids change
/// every 9 voxels along each axis, so faces of one surface stop merging at the shades' edges,
/// as on a model painted in regions.
pub fn menger_shaded(level: u32) -> VoxelBox {
    menger_with(
        level,
        &[
            Material::opaque(150, 150, 160),
            Material::opaque(120, 120, 130),
            Material::opaque(180, 175, 165),
        ],
    )
}

/// The Menger sponge of `level` in `shades`: one shade for all of it, or one per block of
/// [`SHADE_BLOCK`]^3 voxels.
fn menger_with(level: u32, shades: &[Material]) -> VoxelBox {
    let edge = 3usize.pow(level);
    let mut palette = MaterialPalette::new();
    let ids: Vec<u16> = shades
        .iter()
        .map(|&m| palette.push(m).expect("a fresh palette has room").0)
        .collect();
    let mut scene = VoxelBox::new([edge; 3], palette);
    let mut i = 0;
    for z in 0..edge as u64 {
        for y in 0..edge as u64 {
            for x in 0..edge as u64 {
                if in_menger_sponge(level, [x, y, z]) {
                    let shade = ((x / SHADE_BLOCK + y / SHADE_BLOCK + z / SHADE_BLOCK)
                        % ids.len() as u64) as usize;
                    scene.ids[i] = ids[shade];
                }
                i += 1;
            }
        }
    }
    scene
}

/// The ids of the foliage scene.
#[derive(Clone, Copy, Debug)]
pub struct FoliageIds {
    /// Soil under the grass.
    pub dirt: u16,
    /// The top layer of the ground.
    pub grass: u16,
    /// Trunks and branches.
    pub bark: u16,
    /// Three shades of leaves, mixed within every canopy.
    pub leaves: [u16; 3],
    /// Two shades of grass blades.
    pub blades: [u16; 2],
    /// Two flower colours.
    pub flowers: [u16; 2],
    /// Vines hanging from the canopies.
    pub vine: u16,
}

/// The foliage palette: every material opaque, ids 1 to 12.
pub fn foliage_palette() -> (MaterialPalette, FoliageIds) {
    let mut palette = MaterialPalette::new();
    let mut push = |r, g, b| palette.push(Material::opaque(r, g, b)).expect("room").0;
    let ids = FoliageIds {
        dirt: push(110, 80, 50),
        grass: push(70, 140, 50),
        bark: push(90, 60, 35),
        leaves: [push(40, 120, 40), push(60, 150, 45), push(30, 100, 50)],
        blades: [push(80, 170, 60), push(100, 180, 70)],
        flowers: [push(230, 60, 80), push(240, 220, 70)],
        vine: push(50, 110, 40),
    };
    (palette, ids)
}

/// A forest floor of `dims` (x, y, z): a gently rolling ground of dirt under grass, covered
/// with grass blades (1-3 voxels tall) and flowers, bushes, and trees with thin trunks,
/// branches, vines and canopies of leaves with holes (each leaf voxel present with probability
/// 0.6, its shade drawn per voxel). Deterministic for a `seed`.
pub fn foliage(dims: [usize; 3], seed: u64) -> VoxelBox {
    let (palette, ids) = foliage_palette();
    let mut scene = VoxelBox::new(dims, palette);
    let mut rng = Rng::new(seed);
    let [w, h, d] = dims.map(|v| v as i64);
    let ground = |x: i64, z: i64| {
        let (x, z) = (x as f32, z as f32);
        (3.0 + 1.5 * (x * 0.11).sin() + 1.2 * (z * 0.07 + 1.3).sin()).round() as i64
    };
    // Ground, blades and flowers.
    for z in 0..d {
        for x in 0..w {
            let g = ground(x, z);
            for y in 0..g {
                scene.set([x, y, z], ids.dirt);
            }
            scene.set([x, g, z], ids.grass);
            match rng.below(100) {
                0..=24 => {
                    let blade = ids.blades[rng.below(2) as usize];
                    for y in 1..=1 + rng.below(3) as i64 {
                        scene.set([x, g + y, z], blade);
                    }
                }
                25..=27 => {
                    scene.set([x, g + 1, z], ids.blades[0]);
                    scene.set([x, g + 2, z], ids.flowers[rng.below(2) as usize]);
                }
                _ => {}
            }
        }
    }
    // A blob of leaves with holes, mixed shades.
    let canopy = |scene: &mut VoxelBox, rng: &mut Rng, centre: [i64; 3], r: [f32; 3], keep: u64| {
        let main = rng.below(3) as usize;
        let reach = r.map(|v| v.ceil() as i64);
        for dz in -reach[2]..=reach[2] {
            for dy in -reach[1]..=reach[1] {
                for dx in -reach[0]..=reach[0] {
                    let q = [dx, dy, dz]
                        .iter()
                        .zip(r)
                        .map(|(&o, r)| (o as f32 / r).powi(2))
                        .sum::<f32>();
                    if q > 1.0 || rng.below(100) >= keep {
                        continue;
                    }
                    let at = [centre[0] + dx, centre[1] + dy, centre[2] + dz];
                    if scene.get(at) == 0 {
                        let shade = if rng.below(10) < 7 {
                            main
                        } else {
                            rng.below(3) as usize
                        };
                        scene.set(at, ids.leaves[shade]);
                    }
                }
            }
        }
    };
    // Bushes.
    for _ in 0..(w * d / 700) {
        let (x, z) = (rng.below(w as u64) as i64, rng.below(d as u64) as i64);
        let r = rng.range_f32(1.5, 3.0);
        canopy(
            &mut scene,
            &mut rng,
            [x, ground(x, z) + 2, z],
            [r, r * 0.7, r],
            55,
        );
    }
    // Trees.
    for _ in 0..(w * d / 1100).max(1) {
        let (x, z) = (
            4 + rng.below((w - 8) as u64) as i64,
            4 + rng.below((d - 8) as u64) as i64,
        );
        let base = ground(x, z) + 1;
        let top = (base + 12 + rng.below(((h - base - 20).max(1)) as u64) as i64).min(h - 8);
        let thick = rng.below(10) < 4;
        for y in base..=top {
            scene.set([x, y, z], ids.bark);
            if thick {
                scene.set([x + 1, y, z], ids.bark);
                scene.set([x, y, z + 1], ids.bark);
                scene.set([x + 1, y, z + 1], ids.bark);
            }
        }
        let mut ends = vec![[x, top, z]];
        for _ in 0..2 + rng.below(4) {
            let mut at = [x, base + 4 + rng.below((top - base - 3) as u64) as i64, z];
            let step = [rng.below(3) as i64 - 1, 1, rng.below(3) as i64 - 1];
            for _ in 0..3 + rng.below(6) {
                at = [
                    at[0] + step[0],
                    at[1] + rng.below(2) as i64,
                    at[2] + step[2],
                ];
                scene.set(at, ids.bark);
            }
            ends.push(at);
        }
        for end in ends {
            let r = rng.range_f32(3.0, 7.0);
            canopy(&mut scene, &mut rng, end, [r, r * 0.75, r], 60);
            // Vines from the canopy's underside.
            for _ in 0..rng.below(4) {
                let vx = end[0] + rng.below(5) as i64 - 2;
                let vz = end[2] + rng.below(5) as i64 - 2;
                let from = end[1] - (r * 0.6) as i64;
                for y in (from - 2 - rng.below(6) as i64)..from {
                    scene.set([vx, y, vz], ids.vine);
                }
            }
        }
    }
    scene
}

/// A maze of `cells` x `cells` cells in one stone id, flat: a floor one voxel thick (y = 0)
/// under walls `wall_height` voxels high, walls and paths one voxel wide (edge `2 cells + 1`
/// along x and z, height `wall_height + 1`). Its passages are carved by a depth-first walk
/// from cell (0, 0), so every cell is reachable. Seen edge on, most rows of ids hold a solid
/// voxel while the chunks it crosses show few faces per solid voxel, as in a game level's
/// floor plan. Deterministic for a `seed`.
pub fn flat_maze(cells: usize, wall_height: usize, seed: u64) -> VoxelBox {
    let edge = 2 * cells + 1;
    let mut palette = MaterialPalette::new();
    let stone = palette
        .push(Material::opaque(150, 150, 160))
        .expect("room")
        .0;
    let mut scene = VoxelBox::new([edge, wall_height + 1, edge], palette);
    // Walls everywhere, then the cells and the passages between them carved out.
    let mut open = vec![false; edge * edge];
    let mut visited = vec![false; cells * cells];
    let mut rng = Rng::new(seed);
    let mut stack = vec![(0usize, 0usize)];
    visited[0] = true;
    open[edge + 1] = true;
    while let Some(&(cx, cz)) = stack.last() {
        let next: Vec<(usize, usize)> = [(0, 1), (2, 1), (1, 0), (1, 2)]
            .into_iter()
            .filter_map(|(dx, dz)| {
                let (x, z) = ((cx + dx).checked_sub(1)?, (cz + dz).checked_sub(1)?);
                (x < cells && z < cells && !visited[x + cells * z]).then_some((x, z))
            })
            .collect();
        if next.is_empty() {
            stack.pop();
            continue;
        }
        let (nx, nz) = next[rng.below(next.len() as u64) as usize];
        visited[nx + cells * nz] = true;
        // The cell and the wall between it and the last one.
        open[(2 * nx + 1) + edge * (2 * nz + 1)] = true;
        open[(cx + nx + 1) + edge * (cz + nz + 1)] = true;
        stack.push((nx, nz));
    }
    for z in 0..edge {
        for x in 0..edge {
            let height = if open[x + edge * z] { 0 } else { wall_height };
            for y in 0..=height {
                scene.set([x, y, z].map(|a| a as i64), stone);
            }
        }
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shaded_sponge_has_the_sponge_s_holes_and_a_shade_per_block() {
        let plain = menger(3);
        let shaded = menger_shaded(3);
        assert_eq!(shaded.palette.len(), 4, "air and three shades");
        let mut seen = std::collections::BTreeSet::new();
        for (i, (&a, &b)) in plain.ids.iter().zip(&shaded.ids).enumerate() {
            assert_eq!(a != 0, b != 0, "voxel {i}");
            if b == 0 {
                continue;
            }
            seen.insert(b);
            let [x, y, z] = [i % 27, i / 27 % 27, i / 729].map(|a| a as u64 / SHADE_BLOCK);
            assert_eq!(u64::from(b - 1), (x + y + z) % 3, "voxel {i}");
        }
        assert_eq!(seen.len(), 3);
    }

    #[test]
    fn menger_sponge_has_20_cubes_per_level() {
        for level in 1..=3 {
            let scene = menger(level);
            assert_eq!(scene.solid_voxels(), 20usize.pow(level));
        }
        // The centre and the face centres of level 1 are holes; the corners are not.
        assert!(!in_menger_sponge(1, [1, 1, 1]));
        assert!(!in_menger_sponge(1, [1, 1, 0]));
        assert!(in_menger_sponge(1, [0, 0, 0]));
        assert!(in_menger_sponge(1, [1, 0, 0]));
    }

    #[test]
    fn chunks_hold_every_solid_voxel_once() {
        let scene = menger(3);
        for size in [ChunkSize::S16, ChunkSize::S32] {
            let chunks = scene.padded_chunks(size);
            let e = size.edge();
            let interior: usize = chunks
                .iter()
                .map(|c| {
                    let mut n = 0;
                    for z in 1..=e {
                        for y in 1..=e {
                            for x in 1..=e {
                                n += usize::from(!c.get(x, y, z).unwrap().is_air());
                            }
                        }
                    }
                    n
                })
                .sum();
            assert_eq!(interior, scene.solid_voxels(), "{size:?}");
        }
    }

    #[test]
    fn flat_maze_reaches_every_cell_from_the_first() {
        let (cells, height) = (20, 2);
        let maze = flat_maze(cells, height, 7);
        assert_eq!(maze.ids, flat_maze(cells, height, 7).ids);
        let edge = 2 * cells + 1;
        assert_eq!(maze.dims, [edge, height + 1, edge]);
        // The floor is whole; above it, a column is wall (full height) or path (air).
        for z in 0..edge as i64 {
            for x in 0..edge as i64 {
                assert_eq!(maze.get([x, 0, z]), 1);
                let wall = maze.get([x, 1, z]) != 0;
                assert!((1..=height as i64).all(|y| (maze.get([x, y, z]) != 0) == wall));
            }
        }
        // A flood fill over the paths from cell (0, 0) reaches every cell, and a perfect maze
        // (a tree) has exactly cells^2 - 1 passages between cells.
        let path = |x: i64, z: i64| maze.get([x, 1, z]) == 0;
        let mut seen = vec![false; edge * edge];
        let mut todo = vec![(1i64, 1i64)];
        seen[edge + 1] = true;
        while let Some((x, z)) = todo.pop() {
            for (nx, nz) in [(x - 1, z), (x + 1, z), (x, z - 1), (x, z + 1)] {
                let i = (nx + edge as i64 * nz) as usize;
                if path(nx, nz) && !seen[i] {
                    seen[i] = true;
                    todo.push((nx, nz));
                }
            }
        }
        let reached = (0..cells * cells)
            .filter(|c| seen[(2 * (c % cells) + 1) + edge * (2 * (c / cells) + 1)])
            .count();
        assert_eq!(reached, cells * cells);
        let paths = seen.iter().filter(|&&s| s).count();
        assert_eq!(paths, cells * cells + (cells * cells - 1));
    }

    #[test]
    fn foliage_is_deterministic_and_mixed() {
        let a = foliage([64, 48, 64], 3);
        let b = foliage([64, 48, 64], 3);
        assert_eq!(a.ids, b.ids);
        let (_, ids) = foliage_palette();
        let count = |id: u16| a.ids.iter().filter(|&&v| v == id).count();
        for id in [ids.dirt, ids.grass, ids.bark, ids.blades[0], ids.blades[1]] {
            assert!(count(id) > 0, "id {id} missing");
        }
        let leaves: usize = ids.leaves.iter().map(|&id| count(id)).sum();
        assert!(leaves > 500, "{leaves} leaves");
        assert!(ids.leaves.iter().all(|&id| count(id) > 50));
    }
}
