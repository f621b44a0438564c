//! Level-of-detail nodes of the terrain straight from its functions, for a terrain streamed
//! without bounds: the padded neighbourhood of any node of any level, with no world map and no
//! finer level generated first.
//!
//! A node of level `k` is a chunk whose voxels ("cells") are `2^k` blocks wide (see
//! `mesher::lod`). **Level 0** is exact: the blocks of [`Terrain::block_in_column`], caves
//! included, the same blocks [`terrain_scene`](super::terrain_scene) stores (nothing below
//! y = 0, as there). **Coarser levels** follow the mesher's downsampling rule that matters for
//! drawing, *a cell is air only when all its blocks are*, computed from the column heights:
//!
//! - a cell is solid when some column under it reaches into it (`max ground >= cell bottom`,
//!   and the cell is not below y = 0); its id is the block at the cell's top in the tallest
//!   column (grass, snow, sand on top, dirt and stone below);
//! - otherwise it is water when some block in it is water (below the sea level, above the
//!   lowest column's ground);
//! - otherwise air.
//!
//! Caves are not carved at coarse levels: a cell inside a cave is solid. So a coarse node's
//! solid space contains the finer nodes' solid space (caves aside), which is what bounds its
//! surface error by `2^k - 1` blocks (`gpu_backend::cull::lod`) and what keeps a coarse node
//! from showing sky where a finer one shows ground. Each cell reads the height of every one
//! of its `4^k` columns, so a node costs `(edge + 2)^2 * 4^k` height samples: about the area it
//! covers, whatever its level.

use voxel_core::{BlockId, ChunkCoord, ChunkSize, PaddedChunk};

use super::{TERRAIN_TOP, Terrain};

/// What a filled node holds (lets a caller skip meshing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeContent {
    /// Every voxel of the node itself is air: nothing to draw.
    Empty,
    /// Every voxel of the padded neighbourhood is opaque: nothing to draw, whatever the
    /// neighbours' levels (its skirts would face solid space).
    Buried,
    /// Anything else: mesh it.
    Surface,
}

/// The heights under one cell column: lowest and highest ground, and where the highest is.
#[derive(Clone, Copy, Debug)]
struct CellColumn {
    /// Lowest ground.
    min: i32,
    /// Highest ground.
    max: i32,
    /// The tallest column (x, z).
    top: (i32, i32),
    /// False when the cell column lies outside the i32 world (all air).
    exists: bool,
}

impl Terrain {
    /// Fills `padded` with the padded neighbourhood of node `coord` of `level` in chunks of
    /// `size` (see the [module docs](self) for the rule) and says whether it has anything to
    /// draw. Levels above 30 are refused (a cell would be wider than the i32 world).
    pub fn fill_node(
        &self,
        size: ChunkSize,
        level: u32,
        coord: ChunkCoord,
        padded: &mut PaddedChunk,
    ) -> Result<NodeContent, String> {
        if level > 30 {
            return Err(format!(
                "level {level} has cells of 2^{level} blocks, wider than the i32 world"
            ));
        }
        let edge = i64::from(size.edge());
        let p = size.padded_edge();
        let cell = 1i64 << level;
        // Cell index (in cells of this level) of padded position 0 on each axis.
        let origin = [
            i64::from(coord.x) * edge - 1,
            i64::from(coord.y) * edge - 1,
            i64::from(coord.z) * edge - 1,
        ];
        let columns: Vec<CellColumn> = (0..p * p)
            .map(|i| {
                let (px, pz) = ((i % p) as i64, (i / p) as i64);
                self.cell_column((origin[0] + px) * cell, (origin[2] + pz) * cell, cell)
            })
            .collect();
        let mut any_inside = false;
        let mut all_opaque = true;
        let last = p as u32 - 1;
        *padded = PaddedChunk::from_fn(size, |px, py, pz| {
            let column = &columns[px as usize + p * pz as usize];
            let y0 = (origin[1] + i64::from(py)) * cell;
            let id = if level == 0 {
                self.exact_block(column, y0)
            } else {
                self.cell_block(column, y0, y0 + cell)
            };
            let inside = (1..last).contains(&px) && (1..last).contains(&py);
            if inside && (1..last).contains(&pz) && !id.is_air() {
                any_inside = true;
            }
            if id.is_air() || id == self.blocks.water {
                all_opaque = false;
            }
            id
        });
        Ok(if !any_inside {
            NodeContent::Empty
        } else if all_opaque {
            NodeContent::Buried
        } else {
            NodeContent::Surface
        })
    }

    /// The voxel of cell `cell` (in cells of `level`, `2^level` blocks wide) by the rule of
    /// [`fill_node`](Self::fill_node): the same value the fill gives at that cell, for a
    /// caller that needs a few cells without filling a whole node. Reads the `4^level`
    /// column heights under the cell.
    pub fn node_cell(&self, level: u32, cell: [i64; 3]) -> Result<BlockId, String> {
        if level > 30 {
            return Err(format!(
                "level {level} has cells of 2^{level} blocks, wider than the i32 world"
            ));
        }
        let width = 1i64 << level;
        let column = self.cell_column(cell[0] * width, cell[2] * width, width);
        let y0 = cell[1] * width;
        Ok(if level == 0 {
            self.exact_block(&column, y0)
        } else {
            self.cell_block(&column, y0, y0 + width)
        })
    }

    /// The heights under the `cell x cell` columns from block `(x0, z0)`.
    fn cell_column(&self, x0: i64, z0: i64, cell: i64) -> CellColumn {
        let world = i64::from(i32::MIN)..=i64::from(i32::MAX);
        let mut out = CellColumn {
            min: i32::MAX,
            max: i32::MIN,
            top: (0, 0),
            exists: false,
        };
        for z in z0..z0 + cell {
            for x in x0..x0 + cell {
                if !(world.contains(&x) && world.contains(&z)) {
                    continue;
                }
                let (x, z) = (x as i32, z as i32);
                let h = self.height(x, z);
                out.exists = true;
                out.min = out.min.min(h);
                if h > out.max {
                    out.max = h;
                    out.top = (x, z);
                }
            }
        }
        out
    }

    /// Level 0: the exact block at height `y` of the (single) column.
    fn exact_block(&self, column: &CellColumn, y: i64) -> BlockId {
        if !column.exists || !(0..=i64::from(TERRAIN_TOP)).contains(&y) {
            return BlockId::AIR;
        }
        let (x, z) = column.top;
        self.block_in_column(x, y as i32, z, column.max)
    }

    /// A coarse cell spanning heights `y0..y1` over `column` (see the [module docs](self)).
    fn cell_block(&self, column: &CellColumn, y0: i64, y1: i64) -> BlockId {
        // Nothing below y = 0 (as in the stored terrain) or outside the i32 world.
        let bottom = y0.max(0);
        if !column.exists || y1 <= bottom {
            return BlockId::AIR;
        }
        let max = i64::from(column.max);
        if max >= bottom {
            let top = (y1 - 1).min(max) as i32;
            return self.material(column.max, top);
        }
        let sea = i64::from(self.sea_level);
        let lowest_water = bottom.max(i64::from(column.min) + 1);
        if lowest_water <= (y1 - 1).min(sea) {
            self.blocks.water
        } else {
            BlockId::AIR
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_cells_equal_the_fill() {
        let t = terrain();
        let size = ChunkSize::S8;
        for (level, coord) in [
            (0, ChunkCoord::new(0, 1, 0)),
            (1, ChunkCoord::new(-1, 0, 2)),
            (3, ChunkCoord::new(0, 0, 0)),
        ] {
            let mut padded = PaddedChunk::new(size);
            t.fill_node(size, level, coord, &mut padded).unwrap();
            let e = i64::from(size.edge());
            for (px, py, pz) in [(0, 0, 0), (1, 1, 1), (4, 3, 7), (9, 9, 9), (5, 2, 0)] {
                let cell = [
                    i64::from(coord.x) * e - 1 + px,
                    i64::from(coord.y) * e - 1 + py,
                    i64::from(coord.z) * e - 1 + pz,
                ];
                assert_eq!(
                    t.node_cell(level, cell).unwrap(),
                    padded.get(px as u32, py as u32, pz as u32).unwrap(),
                    "level {level} cell {cell:?}"
                );
            }
        }
        assert!(t.node_cell(31, [0, 0, 0]).is_err());
    }
    use crate::terrain::{TerrainBlocks, terrain_scene};
    use voxel_core::storage::gather_neighbourhood;

    fn terrain() -> Terrain {
        Terrain::new(5, TerrainBlocks::palette().1)
    }

    #[test]
    fn level_zero_is_the_stored_terrain() {
        let size = ChunkSize::S16;
        let scene = terrain_scene(5, size, 4, 4, 4);
        let t = terrain();
        let (mut want, mut got) = (PaddedChunk::new(size), PaddedChunk::new(size));
        // The region's inner chunks: their whole neighbourhood is stored (or air above).
        for z in -1..1 {
            for y in 0..3 {
                for x in -1..1 {
                    let coord = ChunkCoord::new(x, y, z);
                    gather_neighbourhood(&scene.world, coord, &mut want);
                    let content = t.fill_node(size, 0, coord, &mut got).unwrap();
                    assert_eq!(want.voxels(), got.voxels(), "chunk {coord:?}");
                    assert_eq!(want.columns(), got.columns(), "masks of {coord:?}");
                    let air = scene.world.get(coord).is_none();
                    assert_eq!(content == NodeContent::Empty, air, "{coord:?}: {content:?}");
                }
            }
        }
    }

    #[test]
    fn a_coarse_cell_is_air_only_where_all_its_blocks_are() {
        let size = ChunkSize::S8;
        let t = terrain();
        let mut padded = PaddedChunk::new(size);
        for level in 1..=3u32 {
            let cell = 1i32 << level;
            for coord in [ChunkCoord::new(0, 0, 0), ChunkCoord::new(-1, 0, 2)] {
                t.fill_node(size, level, coord, &mut padded).unwrap();
                let mut solid_cells = 0;
                for cz in 0..8u32 {
                    for cy in 0..8u32 {
                        for cx in 0..8u32 {
                            let id = padded.get(cx + 1, cy + 1, cz + 1).unwrap();
                            let base = |c: i32, l: u32| (c * 8 + l as i32) * cell;
                            let (x0, y0, z0) =
                                (base(coord.x, cx), base(coord.y, cy), base(coord.z, cz));
                            // Caves left aside: a block below its column's ground is solid.
                            let mut solid = false;
                            let mut water = false;
                            for z in z0..z0 + cell {
                                for x in x0..x0 + cell {
                                    let ground = t.height(x, z);
                                    for y in y0.max(0)..y0 + cell {
                                        solid |= y <= ground;
                                        water |= y > ground && y <= t.sea_level;
                                    }
                                }
                            }
                            let what = format!("level {level} cell {cx},{cy},{cz} of {coord:?}");
                            assert_eq!(!id.is_air() && id != t.blocks.water, solid, "{what}");
                            assert_eq!(id == t.blocks.water, water && !solid, "{what}");
                            solid_cells += usize::from(solid);
                        }
                    }
                }
                assert!(solid_cells > 0, "level {level} {coord:?} has ground");
            }
        }
    }

    #[test]
    fn empty_and_buried_nodes_are_told_apart_and_bad_levels_refused() {
        let size = ChunkSize::S16;
        let t = terrain();
        let mut padded = PaddedChunk::new(size);
        let sky = t.fill_node(size, 0, ChunkCoord::new(0, 5, 0), &mut padded);
        assert_eq!(sky, Ok(NodeContent::Empty));
        let below = t.fill_node(size, 2, ChunkCoord::new(3, -1, 3), &mut padded);
        assert_eq!(below, Ok(NodeContent::Empty), "nothing below y = 0");
        let ground = t.fill_node(size, 1, ChunkCoord::new(0, 0, 0), &mut padded);
        assert_eq!(ground, Ok(NodeContent::Surface));
        assert!(
            t.fill_node(size, 31, ChunkCoord::new(0, 0, 0), &mut padded)
                .is_err()
        );
        // The far edge of the i32 world: no panic, air past the edge.
        let edge = ChunkCoord::new(i32::MAX / 16, 0, i32::MIN / 16);
        assert!(t.fill_node(size, 0, edge, &mut padded).is_ok());
    }
}
