//! The GPU benchmark's scene: the viewer's procedural terrain (heightmap, caves, water) over a
//! square of `side x side` block columns, meshed by the mesher into greedy quads, its chunks
//! ordered nearest to the centre column first so that "the first `n` chunks" is a smaller
//! square of the same terrain.
//!
//! ```
//! use benches::gpu_scene::MeshedTerrain;
//! use voxel_core::ChunkSize;
//!
//! let terrain = MeshedTerrain::generate(64, ChunkSize::S16, 1).unwrap();
//! assert!(terrain.meshes.iter().all(|m| !m.is_empty()));
//! assert!(terrain.quad_count(terrain.meshes.len()) > 0);
//! ```

use std::time::Instant;

use mesher::{BlockClasses, ChunkMesh, MeshError, MeshSettings, mesh_chunks};
use voxel_core::{ChunkCoord, ChunkSize, MaterialPalette};
use voxel_scene::terrain_scene;

/// Highest block the terrain reaches, with margin: `Terrain::base_height + amplitude`, rounded
/// up (the sea is lower).
const TERRAIN_TOP: u32 = 40;

/// A meshed terrain and what making it cost.
pub struct MeshedTerrain {
    /// Chunk edge.
    pub size: ChunkSize,
    /// Block columns per side of the square.
    pub side: u32,
    /// The materials the quads' block ids index.
    pub palette: MaterialPalette,
    /// Every chunk with something to draw, nearest to the centre column first (square rings:
    /// by the larger of `|x|` and `|z|`, then by coordinate).
    pub meshes: Vec<ChunkMesh>,
    /// Seconds to generate the voxels (all threads).
    pub generate_seconds: f64,
    /// Seconds to mesh every chunk (all threads).
    pub mesh_seconds: f64,
    /// Chunks meshed, empty ones included.
    pub chunks_meshed: usize,
}

impl MeshedTerrain {
    /// Generates and meshes the terrain of `side x side` columns (rounded up to whole chunks),
    /// centred on the origin, with greedy quads and ambient occlusion.
    pub fn generate(side: u32, size: ChunkSize, seed: i32) -> Result<MeshedTerrain, MeshError> {
        let edge = size.edge();
        let across = side.div_ceil(edge).max(1) as i32;
        let tall = TERRAIN_TOP.div_ceil(edge) as i32;
        let started = Instant::now();
        let scene = terrain_scene(seed, size, across, tall, across);
        let generate_seconds = started.elapsed().as_secs_f64();
        let mut coords: Vec<ChunkCoord> = scene.world.iter().map(|(c, _)| c).collect();
        coords.sort_by_key(|c| (c.x.abs().max(c.z.abs()), c.x, c.z, c.y));
        let classes = BlockClasses::from_palette(&scene.palette);
        let started = Instant::now();
        let meshes = mesh_chunks(&scene.world, &coords, &classes, &MeshSettings::default())?;
        let mesh_seconds = started.elapsed().as_secs_f64();
        Ok(MeshedTerrain {
            size,
            side: across as u32 * edge,
            palette: scene.palette,
            chunks_meshed: meshes.len(),
            meshes: meshes.into_iter().filter(|m| !m.is_empty()).collect(),
            generate_seconds,
            mesh_seconds,
        })
    }

    /// Greedy quads (both layers) of the first `n` chunks.
    pub fn quad_count(&self, n: usize) -> u64 {
        self.meshes[..n.min(self.meshes.len())]
            .iter()
            .map(|m| m.blocky.len() as u64)
            .sum()
    }

    /// Block columns per side of the square the first `n` chunks cover (the larger of their
    /// x and z spans).
    pub fn covered_side(&self, n: usize) -> u32 {
        let chunks = &self.meshes[..n.min(self.meshes.len())];
        let span = |axis: fn(&ChunkMesh) -> i32| {
            let lo = chunks.iter().map(axis).min().unwrap_or(0);
            let hi = chunks.iter().map(axis).max().unwrap_or(-1);
            (hi - lo + 1) as u32
        };
        span(|m| m.coord.x).max(span(|m| m.coord.z)) * self.size.edge()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_come_nearest_first_and_cover_the_square() {
        let terrain = MeshedTerrain::generate(96, ChunkSize::S16, 3).unwrap();
        assert_eq!(terrain.side, 96);
        let rings: Vec<i32> = terrain
            .meshes
            .iter()
            .map(|m| m.coord.x.abs().max(m.coord.z.abs()))
            .collect();
        assert!(rings.windows(2).all(|w| w[0] <= w[1]), "rings ascend");
        // Every column of chunks has ground, so every (x, z) appears.
        for x in -3..3 {
            for z in -3..3 {
                assert!(
                    terrain
                        .meshes
                        .iter()
                        .any(|m| m.coord.x == x && m.coord.z == z),
                    "column ({x}, {z}) has no meshed chunk"
                );
            }
        }
        assert!(terrain.chunks_meshed >= terrain.meshes.len());
        assert!(terrain.quad_count(1) < terrain.quad_count(terrain.meshes.len()));
        assert_eq!(terrain.covered_side(1), 16);
    }
}
