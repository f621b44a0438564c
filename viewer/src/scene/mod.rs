//! Scenes the viewer shows: the built-in procedural terrain and MagicaVoxel `.vox` files, both
//! generated or loaded by the `voxel-scene` crate (re-exported here as [`terrain`] and
//! [`vox`]), with a first camera view.

use render_model::Camera;
use voxel_core::storage::{PaletteChunk, WorldMap};
use voxel_core::{ChunkSize, MaterialPalette};

pub use voxel_scene::{Terrain, TerrainBlocks, terrain, vox};

/// A world ready to mesh or render: its chunks and the materials their ids index.
#[derive(Debug)]
pub struct Scene {
    /// The voxels, palette-compressed per chunk.
    pub world: WorldMap<PaletteChunk>,
    /// The materials of the ids in `world`.
    pub palette: MaterialPalette,
    /// A good first camera position and direction for this scene.
    pub suggested_view: Camera,
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
    let voxel_scene::TerrainScene {
        world,
        palette,
        terrain,
    } = voxel_scene::terrain_scene(seed, size, chunks_x, chunks_y, chunks_z);
    let suggested_view = terrain_view(&terrain);
    Scene {
        world,
        palette,
        suggested_view,
    }
}

/// The built-in terrain's first view: 14 blocks above the ground (or the sea) at `(0, 40)`,
/// looking over the hills, 70-degree vertical field of view.
pub fn terrain_view(terrain: &Terrain) -> Camera {
    let eye_y = terrain.height(0, 40).max(terrain.sea_level) + 14;
    Camera {
        voxel: voxel_core::WorldPos::new(0, eye_y, 40),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.35,
        pitch: -0.32,
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// A camera that frames the box `lo..=hi` (world voxels) from above and to the south-east.
pub fn camera_looking_at(lo: voxel_core::WorldPos, hi: voxel_core::WorldPos) -> Camera {
    let lo_v = glam::DVec3::new(f64::from(lo.x), f64::from(lo.y), f64::from(lo.z));
    let hi_v = glam::DVec3::new(f64::from(hi.x), f64::from(hi.y), f64::from(hi.z)) + 1.0;
    let centre = (lo_v + hi_v) * 0.5;
    let radius = ((hi_v - lo_v).length() * 0.5).max(1.0);
    let fov_y = 60f64.to_radians();
    let direction = glam::DVec3::new(-0.55, -0.45, -0.7).normalize();
    let eye = centre - direction * (radius / (fov_y * 0.5).sin() * 1.05);
    let floor = eye.floor();
    Camera {
        voxel: voxel_core::WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
        fraction: eye - floor,
        yaw: (-direction.x).atan2(-direction.z),
        pitch: direction.y.asin(),
        fov_y,
        near: Camera::DEFAULT_NEAR,
    }
}
