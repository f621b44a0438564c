//! Scenes the viewer can show. Today: the built-in procedural terrain.

pub mod terrain;
pub mod vox;

use rayon::prelude::*;
use voxel_core::storage::{DenseChunk, PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos, MaterialPalette};

pub use terrain::{Terrain, TerrainBlocks};

/// A world ready to mesh or render: its chunks and the materials their ids index.
pub struct Scene {
    /// The voxels, palette-compressed per chunk.
    pub world: WorldMap<PaletteChunk>,
    /// The materials of the ids in `world`.
    pub palette: MaterialPalette,
    /// A good first camera position and direction for this scene.
    pub suggested_view: crate::reference_raycast::Camera,
}

/// Generates the built-in terrain over `chunks_x * chunks_z` chunk columns of `size`, centred on
/// the origin, `chunks_y` chunks tall from y = 0. Chunks are generated in parallel; all-air chunks
/// are not stored.
pub fn terrain_scene(
    seed: i32,
    size: ChunkSize,
    chunks_x: i32,
    chunks_y: i32,
    chunks_z: i32,
) -> Scene {
    let (palette, blocks) = TerrainBlocks::palette();
    let terrain = Terrain::new(seed, blocks);
    let edge = size.edge() as i32;
    let coords: Vec<ChunkCoord> = (-chunks_z / 2..chunks_z - chunks_z / 2)
        .flat_map(|z| {
            (0..chunks_y).flat_map(move |y| {
                (-chunks_x / 2..chunks_x - chunks_x / 2).map(move |x| ChunkCoord::new(x, y, z))
            })
        })
        .collect();
    let chunks: Vec<(ChunkCoord, PaletteChunk)> = coords
        .par_iter()
        .filter_map(|&coord| {
            let mut dense = DenseChunk::new(size);
            let (x0, y0, z0) = (coord.x * edge, coord.y * edge, coord.z * edge);
            for lz in 0..edge {
                for lx in 0..edge {
                    let ground = terrain.height(x0 + lx, z0 + lz);
                    for ly in 0..edge {
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
    let eye_y = terrain.height(0, 40).max(terrain.sea_level) + 14;
    let suggested_view = crate::reference_raycast::Camera {
        voxel: voxel_core::WorldPos::new(0, eye_y, 40),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.35,
        pitch: -0.32,
        fov_y: 70f64.to_radians(),
    };
    Scene {
        world,
        palette,
        suggested_view,
    }
}

/// A camera that frames the box `lo..=hi` (world voxels) from above and to the south-east.
pub fn camera_looking_at(
    lo: voxel_core::WorldPos,
    hi: voxel_core::WorldPos,
) -> crate::reference_raycast::Camera {
    let lo_v = glam::DVec3::new(f64::from(lo.x), f64::from(lo.y), f64::from(lo.z));
    let hi_v = glam::DVec3::new(f64::from(hi.x), f64::from(hi.y), f64::from(hi.z)) + 1.0;
    let centre = (lo_v + hi_v) * 0.5;
    let radius = ((hi_v - lo_v).length() * 0.5).max(1.0);
    let fov_y = 60f64.to_radians();
    let direction = glam::DVec3::new(-0.55, -0.45, -0.7).normalize();
    let eye = centre - direction * (radius / (fov_y * 0.5).sin() * 1.05);
    let floor = eye.floor();
    crate::reference_raycast::Camera {
        voxel: voxel_core::WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
        fraction: eye - floor,
        yaw: (-direction.x).atan2(-direction.z),
        pitch: direction.y.asin(),
        fov_y,
    }
}
