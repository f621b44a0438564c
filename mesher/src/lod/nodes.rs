//! Meshing the nodes of a level-of-detail hierarchy: per chunk of one level, everything a
//! renderer needs to draw it at that level (quads, skirts, and the far-draw blocks with their
//! hiding mask), and the coarser levels of a world, in parallel with feature `parallel`.
//!
//! ```text
//!  level 0 world ──downsample──► level 1 ──► ... ──► level k      (downsample_levels)
//!        │                          │                    │
//!   mesh_nodes(level 0)      mesh_nodes(level 1)   mesh_nodes(level k)
//!        ▼                          ▼                    ▼
//!   NodeMesh { quads (ChunkMesh), skirts, blocks + skirt blocks, hiding mask }
//! ```
//!
//! Every node is meshed once against its real neighbours at its own level; the skirts (see
//! [`super::skirts`]) close its sides wherever the renderer draws a neighbour at another level.

use alloc::vec::Vec;

use voxel_core::formats::{ChunkLayersData, DrawBlock};
use voxel_core::storage::{PaletteChunk, VoxelStorage, WorldMap, gather_neighbourhood};
use voxel_core::{ChunkCoord, FaceDirection, PaddedChunk};

use super::geometry::{Geometry, keep_opaque_runs};
use super::skirts::{Skirts, skirt_blocks, skirt_quads};
use crate::batch::is_trivially_empty;
use crate::surface_blocks::{hiding_mask, transparent_mask};
use crate::{
    BlockClasses, ChunkMesh, ChunkMesher, MeshError, MeshSettings, ShellRun, ShellRuns,
    SurfaceBlocks,
};

/// What to extract per node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodeSettings {
    /// How the node's quads are meshed.
    pub mesh: MeshSettings,
    /// Also extract far-draw data: surface blocks, skirt blocks and the hiding mask (chunks of
    /// at most 16^3: a `DrawBlock` addresses one 16^3 sub-block).
    pub far_blocks: bool,
    /// Which geometry draws the node's opaque blocky surface: greedy quads, or vertical
    /// shells in [`NodeMesh::shells`] (transparent quads and skirts are the same either way).
    pub geometry: Geometry,
}

/// One node, meshed: what a renderer uploads for it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeMesh {
    /// The chunk's coordinate at its level.
    pub coord: ChunkCoord,
    /// Its level: its voxels are `2^level` blocks wide.
    pub level: u32,
    /// Its layers, meshed against its real neighbours.
    pub mesh: ChunkMesh,
    /// Skirt quads (and, with far blocks, skirt blocks) per side.
    pub skirts: Skirts,
    /// Its surface blocks (empty without far blocks).
    pub blocks: Vec<DrawBlock>,
    /// The hiding occupancy of its padded neighbourhood (empty without far blocks).
    pub hiding_mask: Vec<u32>,
    /// The transparent occupancy of its padded neighbourhood (empty without far blocks or
    /// without transparent voxels).
    pub transparent_mask: Vec<u32>,
    /// Its opaque vertical shells or heightmap boxes (empty unless meshed with
    /// [`Geometry::Shells`] or [`Geometry::Heightmap`], which then
    /// leaves the opaque greedy quads empty).
    pub shells: Vec<ShellRun>,
}

impl NodeMesh {
    /// True when the node draws nothing at all, whatever its neighbours' levels.
    pub fn is_empty(&self) -> bool {
        self.mesh.is_empty()
            && self.skirts.quad_counts() == [0; 6]
            && self.skirts.block_counts() == [0; 6]
            && self.blocks.is_empty()
            && self.shells.is_empty()
    }

    /// The upload view of the node: its mesh's layers ([`ChunkMesh::layers`]) plus its skirts
    /// and its far-draw blocks with their hiding and transparent masks.
    pub fn layers(&self) -> ChunkLayersData<'_> {
        let mut layers = self.mesh.layers();
        for face in FaceDirection::ALL {
            let i = usize::from(face.index());
            layers.opaque_skirts[i] = self.skirts.quads(face);
            layers.draw_block_skirts[i] = self.skirts.blocks(face);
        }
        layers.draw_blocks = &self.blocks;
        layers.hiding_mask = &self.hiding_mask;
        layers.transparent_mask = &self.transparent_mask;
        layers.shell_runs = &self.shells;
        layers
    }
}

/// Scratch buffers for meshing one node at a time; reuse one per thread.
#[derive(Clone, Debug, Default)]
pub struct NodeMesher {
    padded: Option<PaddedChunk>,
    chunk: ChunkMesher,
    surface: SurfaceBlocks,
    skirts: Skirts,
    shells: ShellRuns,
}

/// Empties everything `out` holds but its coordinate and level (capacity kept).
fn clear_contents(out: &mut NodeMesh) {
    out.mesh.clear();
    out.skirts.clear();
    out.blocks.clear();
    out.hiding_mask.clear();
    out.transparent_mask.clear();
    out.shells.clear();
}

impl NodeMesher {
    /// A mesher with empty scratch buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Meshes chunk `coord` of `world` (the world of `level`) into `out`. A chunk known to be
    /// buried or absent is left empty without gathering it (a buried chunk's skirts could
    /// only face solid space at every level: a coarse voxel is solid when any child is).
    pub fn mesh_node<C: VoxelStorage>(
        &mut self,
        world: &WorldMap<C>,
        coord: ChunkCoord,
        level: u32,
        classes: &BlockClasses,
        settings: &NodeSettings,
        out: &mut NodeMesh,
    ) -> Result<(), MeshError> {
        out.coord = coord;
        out.level = level;
        clear_contents(out);
        if is_trivially_empty(world, coord, classes) {
            return Ok(());
        }
        let mut padded = self
            .padded
            .take()
            .unwrap_or_else(|| PaddedChunk::new(world.size()));
        gather_neighbourhood(world, coord, &mut padded);
        let result = self.mesh_padded(&padded, coord, level, classes, settings, out);
        self.padded = Some(padded);
        result
    }

    /// Meshes node `coord` of `level` from a padded neighbourhood the caller filled (for
    /// example straight from a procedural generator, with no world map in between) into
    /// `out`: the same extraction as [`mesh_node`](Self::mesh_node) after its gather. On
    /// error `out` is left empty.
    pub fn mesh_padded(
        &mut self,
        padded: &PaddedChunk,
        coord: ChunkCoord,
        level: u32,
        classes: &BlockClasses,
        settings: &NodeSettings,
        out: &mut NodeMesh,
    ) -> Result<(), MeshError> {
        out.coord = coord;
        out.level = level;
        let result = self.extract(padded, coord, classes, settings, out);
        if result.is_err() {
            clear_contents(out);
        }
        result
    }

    fn extract(
        &mut self,
        padded: &PaddedChunk,
        coord: ChunkCoord,
        classes: &BlockClasses,
        settings: &NodeSettings,
        out: &mut NodeMesh,
    ) -> Result<(), MeshError> {
        clear_contents(out);
        self.chunk
            .mesh_gathered(padded, coord, classes, &settings.mesh, &mut out.mesh)?;
        if settings.geometry == Geometry::Heightmap {
            // The boxes' border columns are the skirts; a heightmap draws at every distance,
            // so it has no far-draw data.
            out.mesh.blocky.opaque.clear();
            return crate::heightmap::heightmap_boxes(padded, classes, &mut out.shells);
        }
        skirt_quads(padded, classes, &mut out.skirts)?;
        if settings.geometry == Geometry::Shells {
            out.mesh.blocky.opaque.clear();
            crate::vertical_shells(padded, classes, &mut self.shells)?;
            keep_opaque_runs(
                self.shells.runs(),
                classes,
                settings.mesh.surface,
                &mut out.shells,
            );
        }
        if settings.far_blocks {
            crate::surface_blocks(padded, classes, &mut self.surface)?;
            out.blocks.extend_from_slice(self.surface.blocks());
            // skirt_blocks clears the quads it does not make: keep them aside.
            skirt_blocks(padded, classes, &mut self.skirts)?;
            for side in FaceDirection::ALL {
                let index = usize::from(side.index());
                out.skirts.set_blocks(index, self.skirts.blocks(side));
            }
            hiding_mask(padded, classes, &mut out.hiding_mask);
            transparent_mask(padded, classes, &mut out.transparent_mask);
        }
        Ok(())
    }
}

/// Meshes `coords` of `world` (the world of `level`) one after another; the `no_std`
/// counterpart of [`mesh_nodes`]. Nodes that draw nothing are left out.
pub fn mesh_nodes_sequential<C: VoxelStorage>(
    world: &WorldMap<C>,
    level: u32,
    coords: &[ChunkCoord],
    classes: &BlockClasses,
    settings: &NodeSettings,
) -> Result<Vec<NodeMesh>, MeshError> {
    let mut mesher = NodeMesher::new();
    let mut out = Vec::new();
    for &coord in coords {
        let mut node = NodeMesh::default();
        mesher.mesh_node(world, coord, level, classes, settings, &mut node)?;
        if !node.is_empty() {
            out.push(node);
        }
    }
    Ok(out)
}

/// Meshes `coords` of `world` (the world of `level`) in parallel on rayon's pool, one
/// [`NodeMesher`] per worker thread. Nodes that draw nothing are left out; the rest keep the
/// order of `coords`, whatever the thread count. Returns the first error in `coords` order.
#[cfg(feature = "parallel")]
pub fn mesh_nodes<C: VoxelStorage + Sync>(
    world: &WorldMap<C>,
    level: u32,
    coords: &[ChunkCoord],
    classes: &BlockClasses,
    settings: &NodeSettings,
) -> Result<Vec<NodeMesh>, MeshError> {
    use core::cell::RefCell;
    use rayon::prelude::*;

    std::thread_local! {
        static MESHER: RefCell<NodeMesher> = RefCell::new(NodeMesher::new());
    }
    let nodes: Result<Vec<NodeMesh>, MeshError> = coords
        .par_iter()
        .with_max_len(1)
        .map(|&coord| {
            let mut node = NodeMesh::default();
            MESHER
                .with(|slot| match slot.try_borrow_mut() {
                    Ok(mut mesher) => {
                        mesher.mesh_node(world, coord, level, classes, settings, &mut node)
                    }
                    Err(_) => NodeMesher::new()
                        .mesh_node(world, coord, level, classes, settings, &mut node),
                })
                .map(|()| node)
        })
        .collect();
    Ok(nodes?.into_iter().filter(|n| !n.is_empty()).collect())
}

/// The coarser levels of `world`: entry `k - 1` is level `k`, for `k` in `1..=top`, each the
/// downsampling of the one below ([`super::downsample_world`]); with feature `parallel`, the
/// chunks of each level are downsampled in parallel.
pub fn downsample_levels<C: VoxelStorage + Sync>(
    world: &WorldMap<C>,
    classes: &BlockClasses,
    top: u32,
) -> Result<Vec<WorldMap<PaletteChunk>>, MeshError> {
    let mut levels: Vec<WorldMap<PaletteChunk>> = Vec::new();
    for _ in 0..top {
        let next = match levels.last() {
            None => downsample(world, classes)?,
            Some(previous) => downsample(previous, classes)?,
        };
        levels.push(next);
    }
    Ok(levels)
}

#[cfg(feature = "parallel")]
fn downsample<C: VoxelStorage + Sync>(
    fine: &WorldMap<C>,
    classes: &BlockClasses,
) -> Result<WorldMap<PaletteChunk>, MeshError> {
    super::downsample_world_parallel(fine, classes)
}

#[cfg(not(feature = "parallel"))]
fn downsample<C: VoxelStorage + Sync>(
    fine: &WorldMap<C>,
    classes: &BlockClasses,
) -> Result<WorldMap<PaletteChunk>, MeshError> {
    super::downsample_world(fine, classes)
}
