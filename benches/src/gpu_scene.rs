//! The GPU benchmark's scene: the procedural terrain of `voxel-scene` (the viewer's built-in
//! scene: heightmap, caves, water) over a square of `side x side` block columns centred on the
//! origin, downsampled into levels of detail and meshed per node ([`mesher::lod`]): quads with
//! AO, skirts, and the far-draw blocks with their hiding masks.
//!
//! Generation and meshing run on rayon's pool. Which nodes are meshed is up to the caller
//! ([`LodTerrain::generate`]'s `keep`): everything for a scene that fits, or only what the
//! benchmark's views can select, so that a large terrain keeps only what its views need.
//!
//! ```
//! use benches::gpu_scene::LodTerrain;
//! use voxel_core::ChunkSize;
//!
//! let terrain = LodTerrain::generate(128, ChunkSize::S8, 1, 2, |_, _| true).unwrap();
//! assert_eq!(terrain.levels.len(), 3);
//! assert!(terrain.levels.iter().all(|nodes| !nodes.is_empty()));
//! assert!(terrain.quad_count() > 0);
//! ```

use std::time::Instant;

use mesher::lod::{Geometry, NodeMesh, NodeSettings, downsample_levels, mesh_nodes};
use mesher::{BlockClasses, ClutterParams, MeshError, MeshSettings};
use voxel_core::storage::{VoxelStorage, WorldMap};
use voxel_core::{ChunkCoord, ChunkSize, MaterialPalette};
use voxel_scene::terrain_scene;

/// Highest block the terrain reaches, with margin: `Terrain::base_height + amplitude`, rounded
/// up (the sea is lower).
const TERRAIN_TOP: u32 = 40;

/// Clutter on the level-0 chunks `on` admits (the grass pass draws no other level): the
/// benchmark places it only where its views can draw grass
/// (`render_model::grass::chunk_may_draw_grass`), as the viewer's streamer does.
#[derive(Clone, Copy)]
pub struct Clutter<'a> {
    /// The placement's density and seed.
    pub params: ClutterParams,
    /// Which level-0 chunks get clutter.
    pub on: &'a (dyn Fn(ChunkCoord) -> bool + Sync),
}

impl std::fmt::Debug for Clutter<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Clutter")
            .field("params", &self.params)
            .finish_non_exhaustive()
    }
}

/// A terrain meshed at every level of detail, and what making it cost.
#[derive(Debug)]
pub struct LodTerrain {
    /// Chunk edge.
    pub size: ChunkSize,
    /// Block columns per side of the square.
    pub side: u32,
    /// The materials the quads' block ids index.
    pub palette: MaterialPalette,
    /// Per level (index = level), the nodes kept, nearest to the centre column first.
    pub levels: Vec<Vec<NodeMesh>>,
    /// Chunks per level before the choice of what to mesh.
    pub chunks_per_level: Vec<usize>,
    /// Seconds to generate the level-0 voxels (all threads).
    pub generate_seconds: f64,
    /// Seconds to downsample the coarser levels (all threads).
    pub downsample_seconds: f64,
    /// Seconds to mesh the kept nodes (all threads).
    pub mesh_seconds: f64,
}

impl LodTerrain {
    /// Generates the terrain of `side x side` columns (rounded up to whole chunks), its levels
    /// `1..=top_level`, and meshes the nodes `keep(level, coord)` accepts (with far-draw blocks
    /// when the chunks are at most 16^3), each level's nodes nearest to the centre first.
    pub fn generate(
        side: u32,
        size: ChunkSize,
        seed: i32,
        top_level: u32,
        keep: impl Fn(u32, ChunkCoord) -> bool + Sync,
    ) -> Result<LodTerrain, MeshError> {
        Self::generate_with_clutter(side, size, seed, top_level, None, keep)
    }

    /// [`generate`](Self::generate), with `clutter` placed on the grass of the level-0 chunks
    /// it admits (the only level the grass pass draws).
    pub fn generate_with_clutter(
        side: u32,
        size: ChunkSize,
        seed: i32,
        top_level: u32,
        clutter: Option<Clutter<'_>>,
        keep: impl Fn(u32, ChunkCoord) -> bool + Sync,
    ) -> Result<LodTerrain, MeshError> {
        Self::generate_as(side, size, seed, top_level, clutter, Geometry::Greedy, keep)
    }

    /// [`generate_with_clutter`](Self::generate_with_clutter), the opaque surface of every
    /// node extracted as `geometry` (greedy quads or vertical shells).
    pub fn generate_as(
        side: u32,
        size: ChunkSize,
        seed: i32,
        top_level: u32,
        clutter: Option<Clutter<'_>>,
        geometry: Geometry,
        keep: impl Fn(u32, ChunkCoord) -> bool + Sync,
    ) -> Result<LodTerrain, MeshError> {
        let edge = size.edge();
        let across = side.div_ceil(edge).max(1) as i32;
        let tall = TERRAIN_TOP.div_ceil(edge) as i32;
        let started = Instant::now();
        let scene = terrain_scene(seed, size, across, tall, across);
        let generate_seconds = started.elapsed().as_secs_f64();
        let classes = BlockClasses::from_palette(&scene.palette);
        let started = Instant::now();
        let coarse = downsample_levels(&scene.world, &classes, top_level)?;
        let downsample_seconds = started.elapsed().as_secs_f64();
        let settings = NodeSettings {
            mesh: MeshSettings::default(),
            far_blocks: edge <= 16,
            geometry,
        };
        let started = Instant::now();
        let mut levels = Vec::new();
        let mut chunks_per_level = Vec::new();
        let with_clutter = |c: ChunkCoord| clutter.is_some_and(|cl| (cl.on)(c));
        let plain = |l: u32, c: ChunkCoord| keep(l, c) && !with_clutter(c);
        let (count, mut nodes) = mesh_level(&scene.world, 0, &classes, &settings, &plain)?;
        if let Some(cl) = clutter {
            let level0 = NodeSettings {
                mesh: MeshSettings {
                    clutter: Some(cl.params),
                    ..settings.mesh
                },
                ..settings
            };
            let on = |l: u32, c: ChunkCoord| keep(l, c) && with_clutter(c);
            nodes.extend(mesh_level(&scene.world, 0, &classes, &level0, &on)?.1);
            nodes.sort_by_key(|n| centre_order(n.coord));
        }
        chunks_per_level.push(count);
        levels.push(nodes);
        for (i, world) in coarse.iter().enumerate() {
            let (count, nodes) = mesh_level(world, i as u32 + 1, &classes, &settings, &keep)?;
            chunks_per_level.push(count);
            levels.push(nodes);
        }
        Ok(LodTerrain {
            size,
            side: across as u32 * edge,
            palette: scene.palette,
            levels,
            chunks_per_level,
            generate_seconds,
            downsample_seconds,
            mesh_seconds: started.elapsed().as_secs_f64(),
        })
    }

    /// Every kept node, level after level.
    pub fn nodes(&self) -> impl Iterator<Item = &NodeMesh> {
        self.levels.iter().flatten()
    }

    /// Quads (both layers and the skirts) of every kept node.
    pub fn quad_count(&self) -> u64 {
        self.nodes().map(node_quads).sum()
    }

    /// Shell runs of every kept node (none with greedy geometry).
    pub fn shell_count(&self) -> u64 {
        self.nodes().map(|n| n.shells.len() as u64).sum()
    }

    /// Clutter units of every kept node.
    pub fn clutter_count(&self) -> u64 {
        self.nodes().map(|n| n.mesh.clutter.len() as u64).sum()
    }

    /// Far-draw blocks (surface blocks and skirt blocks, 4 bytes each) of every kept node.
    pub fn far_block_count(&self) -> u64 {
        self.nodes()
            .map(|n| n.blocks.len() as u64 + total(&n.skirts.block_counts()))
            .sum()
    }

    /// Draw-block words (blocks, skirt blocks, hiding masks) of every kept node.
    pub fn draw_block_words(&self) -> u64 {
        self.nodes().map(node_draw_block_words).sum()
    }
}

/// Quads of one node: both layers and the skirts.
pub fn node_quads(node: &NodeMesh) -> u64 {
    node.mesh.blocky.len() as u64 + total(&node.skirts.quad_counts())
}

/// Draw-block words of one node: blocks, skirt blocks, hiding masks.
pub fn node_draw_block_words(node: &NodeMesh) -> u64 {
    (node.blocks.len() + node.hiding_mask.len() + node.transparent_mask.len()) as u64
        + total(&node.skirts.block_counts())
}

/// The sum of per-side counts.
fn total<C: Copy + Into<u64>>(counts: &[C]) -> u64 {
    counts.iter().map(|&c| c.into()).sum()
}

/// Meshes the kept chunks of one level, nearest to the centre column first (square rings, then
/// by coordinate); returns the level's chunk count and the nodes.
fn mesh_level<C: VoxelStorage + Sync>(
    world: &WorldMap<C>,
    level: u32,
    classes: &BlockClasses,
    settings: &NodeSettings,
    keep: &(impl Fn(u32, ChunkCoord) -> bool + Sync),
) -> Result<(usize, Vec<NodeMesh>), MeshError> {
    let mut coords: Vec<ChunkCoord> = world.iter().map(|(c, _)| c).collect();
    let count = coords.len();
    coords.retain(|&c| keep(level, c));
    coords.sort_by_key(|&c| centre_order(c));
    Ok((count, mesh_nodes(world, level, &coords, classes, settings)?))
}

/// The order of a level's nodes: square rings around the centre column, then by coordinate.
fn centre_order(c: ChunkCoord) -> (i32, i32, i32, i32) {
    (c.x.abs().max(c.z.abs()), c.x, c.z, c.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_cover_the_square_and_keep_follows_the_filter() {
        let terrain = LodTerrain::generate(96, ChunkSize::S16, 3, 1, |_, _| true).unwrap();
        assert_eq!(terrain.side, 96);
        let level0 = &terrain.levels[0];
        let rings: Vec<i32> = level0
            .iter()
            .map(|m| m.coord.x.abs().max(m.coord.z.abs()))
            .collect();
        assert!(rings.windows(2).all(|w| w[0] <= w[1]), "rings ascend");
        for x in -3..3 {
            for z in -3..3 {
                assert!(
                    level0.iter().any(|m| m.coord.x == x && m.coord.z == z),
                    "column ({x}, {z}) has no node"
                );
            }
        }
        assert!(terrain.levels[1].iter().all(|n| n.level == 1));
        assert!(
            terrain.draw_block_words() > 0,
            "16^3 chunks carry far-draw blocks"
        );
        let only_coarse =
            LodTerrain::generate(96, ChunkSize::S16, 3, 1, |level, _| level == 1).unwrap();
        assert!(only_coarse.levels[0].is_empty());
        assert_eq!(only_coarse.levels[1].len(), terrain.levels[1].len());
        assert_eq!(only_coarse.chunks_per_level, terrain.chunks_per_level);
    }
}
