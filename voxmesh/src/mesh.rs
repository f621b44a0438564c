//! Meshing every chunk of a world in the chosen mode, in parallel on rayon's current pool.

use mesher::blocky::{BlockyMesh, GreedyMesher};
use mesher::smooth::{NoCubes, SmoothMesh};
use mesher::{BlockClasses, MeshError};
use voxel_core::storage::{PaletteChunk, WorldMap, gather_neighbourhood};
use voxel_core::{ChunkCoord, MaterialPalette, PaddedChunk};

use rayon::prelude::*;

use crate::cli::Mode;

/// The mesh of one chunk.
#[derive(Debug)]
pub struct ChunkOutput {
    /// The chunk.
    pub coord: ChunkCoord,
    /// Quads of opaque and see-through blocks (in smooth mode: the blocks that stay cubes).
    pub blocky: BlockyMesh,
    /// The smooth surface (smooth mode only).
    pub smooth: SmoothMesh,
}

/// The classes the mesher sees: in smooth mode every opaque material is smoothable, so the
/// whole model is smoothed (see-through blocks stay cubes); otherwise the palette's own.
pub fn classes_for(palette: &MaterialPalette, mode: Mode) -> BlockClasses {
    if mode != Mode::Smooth {
        return BlockClasses::from_palette(palette);
    }
    BlockClasses::all_opaque_smoothable(palette)
}

/// Downsamples `world` `levels` times (each level halves the resolution; see
/// `mesher::lod`). Level 0 returns the world unchanged.
pub fn downsample(
    world: WorldMap<PaletteChunk>,
    classes: &BlockClasses,
    levels: u32,
) -> Result<WorldMap<PaletteChunk>, MeshError> {
    let mut world = world;
    for _ in 0..levels {
        world = mesher::lod::downsample_world(&world, classes)?;
    }
    Ok(world)
}

/// Meshes every stored chunk of `world` (chunks not stored are air and have no faces), in
/// coordinate order, calling `done` after each chunk. Chunks with nothing to draw are left out.
pub fn mesh_world(
    world: &WorldMap<PaletteChunk>,
    classes: &BlockClasses,
    mode: Mode,
    ambient_occlusion: bool,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<ChunkOutput>, MeshError> {
    let mut coords: Vec<ChunkCoord> = world.iter().map(|(c, _)| c).collect();
    coords.sort_unstable();
    let meshes: Vec<Option<ChunkOutput>> = coords
        .par_iter()
        .with_max_len(1)
        .map_init(
            || Scratch::new(world, ambient_occlusion),
            |scratch, &coord| {
                let result = scratch.mesh(world, coord, classes, mode);
                done();
                result
            },
        )
        .collect::<Result<_, _>>()?;
    Ok(meshes.into_iter().flatten().collect())
}

/// One thread's buffers.
struct Scratch {
    padded: PaddedChunk,
    greedy: GreedyMesher,
    nocubes: Option<NoCubes>,
}

impl Scratch {
    fn new(world: &WorldMap<PaletteChunk>, ambient_occlusion: bool) -> Scratch {
        Scratch {
            padded: PaddedChunk::new(world.size()),
            greedy: GreedyMesher::new().with_ambient_occlusion(ambient_occlusion),
            nocubes: None,
        }
    }

    fn mesh(
        &mut self,
        world: &WorldMap<PaletteChunk>,
        coord: ChunkCoord,
        classes: &BlockClasses,
        mode: Mode,
    ) -> Result<Option<ChunkOutput>, MeshError> {
        gather_neighbourhood(world, coord, &mut self.padded);
        let mut out = ChunkOutput {
            coord,
            blocky: BlockyMesh::new(),
            smooth: SmoothMesh::new(),
        };
        match mode {
            Mode::Faces => self
                .greedy
                .visible_faces(&self.padded, classes, &mut out.blocky)?,
            Mode::Greedy => self.greedy.mesh(&self.padded, classes, &mut out.blocky)?,
            Mode::Smooth => {
                self.nocubes.get_or_insert_with(NoCubes::new).mesh(
                    &self.padded,
                    classes,
                    &mut out.smooth,
                    &mut out.blocky,
                )?;
            }
        }
        Ok((!out.blocky.is_empty() || !out.smooth.is_empty()).then_some(out))
    }
}
