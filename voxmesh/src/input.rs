//! Loading the input: a `.vox` file or the built-in terrain, as a world of chunks and the
//! material of every block id.

use voxel_core::storage::{PaletteChunk, WorldMap};
use voxel_core::{ChunkSize, MaterialClass, MaterialPalette};
use voxel_scene::vox::{VoxMaterial, VoxMaterialKind, VoxOptions, load_vox_file_with};

use crate::Error;
use crate::cli::Input;

/// Most voxels a `.vox` scene may place: MagicaVoxel scenes top out far below this; the limit
/// keeps a corrupt or hostile file from exhausting memory.
pub const MAX_VOX_VOXELS: usize = 1 << 28;

/// A world to mesh.
#[derive(Debug)]
pub struct Scene {
    /// The voxels.
    pub world: WorldMap<PaletteChunk>,
    /// The renderer's palette of the block ids in `world` (classes decide visibility).
    pub palette: MaterialPalette,
    /// The material of every block id, indexed by id (id 0 is air).
    pub materials: Vec<VoxMaterial>,
    /// Occupied voxels.
    pub voxel_count: usize,
    /// What the user should be told about the input (hidden nodes left out, ...).
    pub notes: Vec<String>,
}

/// Loads `input` into chunks of `size`; `include_hidden` draws hidden `.vox` nodes too.
pub fn load(input: &Input, size: ChunkSize, include_hidden: bool) -> Result<Scene, Error> {
    match input {
        Input::Vox(path) => {
            let options = VoxOptions {
                include_hidden,
                ..VoxOptions::new(size, MAX_VOX_VOXELS)
            };
            let vox = load_vox_file_with(path, &options).map_err(|source| Error::Vox {
                path: path.clone(),
                source,
            })?;
            Ok(Scene {
                world: vox.world,
                palette: vox.palette,
                materials: vox.materials,
                voxel_count: vox.voxel_count,
                notes: vox.report.notes(),
            })
        }
        Input::Terrain { seed, side } => {
            let terrain = voxel_scene::terrain_columns(*seed, size, *side);
            let materials = terrain.palette.as_slice().iter().map(material_of).collect();
            let voxel_count = terrain
                .world
                .iter()
                .map(|(_, c)| voxel_core::storage::VoxelStorage::non_air_count(c))
                .sum();
            Ok(Scene {
                world: terrain.world,
                palette: terrain.palette,
                materials,
                voxel_count,
                notes: Vec::new(),
            })
        }
        Input::World(dir) => load_world(dir, size),
    }
}

/// The stored chunks of the world saved in `dir`, re-chunked into chunks of `size`, with the
/// terrain's palette. A faulty chunk refuses the input by name (voxmesh does not write a mesh
/// with a chunk missing).
fn load_world(dir: &std::path::Path, size: ChunkSize) -> Result<Scene, Error> {
    use voxel_core::storage::VoxelStorage;
    let refuse = |message: String| Error::World {
        path: dir.to_path_buf(),
        message,
    };
    let (world, report) = voxel_world::World::load(voxel_world::AirBase, dir, 0)
        .map_err(|e| refuse(e.to_string()))?;
    if let Some((path, fault)) = report.faults.first() {
        return Err(refuse(format!("{}: {fault}", path.display())));
    }
    let mut out: WorldMap<PaletteChunk> = WorldMap::new(size);
    let mut voxel_count = 0;
    for coord in world.edited() {
        let Some(chunk) = world.chunks().get(coord) else {
            continue;
        };
        for (local, id) in chunk.iter().filter(|(_, id)| !id.is_air()) {
            let pos = coord
                .world_pos(local, world.size())
                .map_err(|e| refuse(e.to_string()))?;
            out.set_block(pos, id);
            voxel_count += 1;
        }
    }
    let (palette, _) = voxel_scene::terrain::TerrainBlocks::palette();
    let materials = palette.as_slice().iter().map(material_of).collect();
    Ok(Scene {
        world: out,
        palette,
        materials,
        voxel_count,
        notes: Vec::new(),
    })
}

/// The export material of one of the renderer's materials (the built-in terrain's):
/// transparent ones see-through by their alpha, emission, roughness and metalness from their
/// bytes.
fn material_of(m: &voxel_core::Material) -> VoxMaterial {
    let mut out = VoxMaterial::diffuse(m.colour);
    if m.class == MaterialClass::Transparent {
        out.kind = VoxMaterialKind::Glass;
        out.transparency = 1.0 - f32::from(m.colour[3]) / 255.0;
        out.colour[3] = 255;
    }
    out.roughness = f32::from(m.roughness) / 255.0;
    out.emission = f32::from(m.emission) / 255.0;
    out.metalness = f32::from(m.metalness) / 255.0;
    if out.metalness > 0.0 && m.class != MaterialClass::Transparent {
        out.kind = VoxMaterialKind::Metal;
    }
    if out.emission > 0.0 {
        out.kind = VoxMaterialKind::Emit;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxel_core::{BlockId, WorldPos};
    use voxel_world::{AirBase, Edit, World};

    #[test]
    fn a_saved_world_is_read_into_any_chunk_size_and_a_missing_one_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mut world = World::new(AirBase, ChunkSize::S8, 0).unwrap();
        let (min, max) = (WorldPos::new(-3, 0, -3), WorldPos::new(9, 2, 4));
        world
            .apply(&[Edit::Box {
                min,
                max,
                id: BlockId(2),
            }])
            .unwrap();
        world.save(dir.path()).unwrap();
        let input = Input::World(dir.path().to_path_buf());
        let scene = load(&input, ChunkSize::S32, false).unwrap();
        assert_eq!(scene.voxel_count, 13 * 3 * 8);
        assert_eq!(scene.world.get_block(WorldPos::new(9, 2, 4)), BlockId(2));
        assert_eq!(scene.world.get_block(WorldPos::new(10, 2, 4)), BlockId::AIR);
        let missing = Input::World(dir.path().join("nothing"));
        let e = load(&missing, ChunkSize::S32, false).unwrap_err();
        assert!(e.to_string().contains("world.vxw"), "{e}");
    }
}
