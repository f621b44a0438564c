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
    }
}

/// The export material of one of the renderer's materials (the built-in terrain's):
/// transparent ones see-through by their alpha, emission and roughness from their bytes.
fn material_of(m: &voxel_core::Material) -> VoxMaterial {
    let mut out = VoxMaterial::diffuse(m.colour);
    if m.class == MaterialClass::Transparent {
        out.kind = VoxMaterialKind::Glass;
        out.transparency = 1.0 - f32::from(m.colour[3]) / 255.0;
        out.colour[3] = 255;
    }
    out.roughness = f32::from(m.roughness) / 255.0;
    out.emission = f32::from(m.emission) / 255.0;
    if out.emission > 0.0 {
        out.kind = VoxMaterialKind::Emit;
    }
    out
}
