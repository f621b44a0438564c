//! Meshing whole chunks of a world: every layer a chunk needs, and many chunks in parallel.
//!
//! [`ChunkMesher`] holds one set of scratch buffers (the padded neighbourhood and each mesher's
//! buffers) and meshes one chunk at a time into a [`ChunkMesh`] of layers: opaque and
//! transparent greedy quads, the smooth (NoCubes) layer, and clutter. A layer a chunk does not
//! need stays empty and costs nothing to upload.
//!
//! Chunks whose mesh is known to be empty are not gathered at all: a chunk that is not stored
//! (all air), and a uniform opaque chunk whose six face neighbours are uniform opaque too
//! (buried). Checking that is a few map look-ups.
//!
//! With feature `parallel`, [`mesh_chunks`] meshes a list of chunks on rayon's pool with one
//! `ChunkMesher` per worker thread, kept between calls; the result is in the order of the list
//! and does not depend on the number of threads (each chunk's mesh depends only on the world).

use alloc::vec::Vec;

use voxel_core::formats::ChunkLayersData;
use voxel_core::storage::{VoxelStorage, WorldMap, gather_neighbourhood};
use voxel_core::{ChunkCoord, FaceDirection, PaddedChunk};

use crate::blocky::{BlockyMesh, GreedyMesher};
use crate::smooth::{NoCubes, SmoothMesh};
use crate::{BlockClasses, ClutterLayer, ClutterParams, MeshError, place_clutter};

/// How the surface of a chunk's blocks is extracted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SurfaceMode {
    /// Greedy quads with ambient occlusion (the default).
    #[default]
    Greedy,
    /// One quad per visible face, with ambient occlusion.
    VisibleFaces,
    /// NoCubes: smoothable blocks as a smooth surface (the smooth layer), the other blocks as
    /// greedy quads (cube faces in the opaque layer, transparent blocks in theirs). The same
    /// as `Greedy` when the palette has no smoothable material.
    NoCubes,
}

/// What to extract for each chunk.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshSettings {
    /// How block surfaces are meshed.
    pub surface: SurfaceMode,
    /// Clutter to place on clutter-bearing top faces; `None` places none.
    pub clutter: Option<ClutterParams>,
}

/// The layers of one meshed chunk. Empty layers are empty vectors: nothing to upload.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChunkMesh {
    /// The chunk this mesh belongs to.
    pub coord: ChunkCoord,
    /// Opaque and transparent quads (in `NoCubes` mode the opaque layer has no quads of
    /// smoothable blocks).
    pub blocky: BlockyMesh,
    /// The NoCubes smooth surface (vertices and quads; empty in the other modes).
    pub smooth: SmoothMesh,
    /// Clutter units.
    pub clutter: ClutterLayer,
}

impl ChunkMesh {
    /// Empties every layer, keeping capacity.
    pub fn clear(&mut self) {
        self.blocky.clear();
        self.smooth.clear();
        self.clutter.clear();
    }

    /// True when no layer has anything to draw.
    pub fn is_empty(&self) -> bool {
        self.blocky.is_empty() && self.smooth.is_empty() && self.clutter.is_empty()
    }

    /// The upload view of the layers: the mesher's buffers as they are, borrowed (the smooth
    /// quads in the form the mesh chose, compact where it fits), in the form a GPU backend
    /// uploads ([`ChunkLayersData`]). Nothing is copied or re-encoded: the mesher writes the
    /// packed formats the GPU reads.
    pub fn layers(&self) -> ChunkLayersData<'_> {
        let mut layers = ChunkLayersData {
            smooth_vertices: self.smooth.vertices(),
            smooth_quads: self.smooth.quads(),
            clutter_units: self.clutter.units(),
            ..Default::default()
        };
        for face in FaceDirection::ALL {
            let i = usize::from(face.index());
            layers.opaque_quads[i] = self.blocky.opaque.face(face);
            layers.transparent_quads[i] = self.blocky.transparent.face(face);
        }
        layers
    }

    /// Bytes of packed GPU data in all layers (8 per quad, the smooth layer's exact size, 20
    /// per clutter unit).
    pub fn byte_len(&self) -> usize {
        self.blocky.len() * 8 + self.smooth.byte_len() + self.clutter.len() * 20
    }
}

/// Scratch buffers for meshing one chunk at a time; reuse one per thread.
#[derive(Clone, Debug, Default)]
pub struct ChunkMesher {
    padded: Option<PaddedChunk>,
    greedy: GreedyMesher,
    nocubes: Option<NoCubes>,
}

impl ChunkMesher {
    /// A mesher with empty scratch buffers (they grow on first use and are kept).
    pub fn new() -> Self {
        Self::default()
    }

    /// Meshes chunk `coord` of `world` into `out` (cleared first), gathering its neighbourhood
    /// unless its mesh is known to be empty. On error `out` is left empty.
    pub fn mesh_chunk<C: VoxelStorage>(
        &mut self,
        world: &WorldMap<C>,
        coord: ChunkCoord,
        classes: &BlockClasses,
        settings: &MeshSettings,
        out: &mut ChunkMesh,
    ) -> Result<(), MeshError> {
        out.clear();
        out.coord = coord;
        if is_trivially_empty(world, coord, classes) {
            return Ok(());
        }
        let padded = self
            .padded
            .get_or_insert_with(|| PaddedChunk::new(world.size()));
        gather_neighbourhood(world, coord, padded);
        let result = mesh_padded(
            padded,
            coord,
            classes,
            settings,
            &mut self.greedy,
            &mut self.nocubes,
            out,
        );
        if result.is_err() {
            out.clear();
        }
        result
    }
}

impl ChunkMesher {
    /// Meshes an already gathered neighbourhood (`padded`, the chunk at `coord` with its
    /// border) into `out` (cleared first). On error `out` is left empty.
    pub fn mesh_gathered(
        &mut self,
        padded: &PaddedChunk,
        coord: ChunkCoord,
        classes: &BlockClasses,
        settings: &MeshSettings,
        out: &mut ChunkMesh,
    ) -> Result<(), MeshError> {
        out.clear();
        out.coord = coord;
        let result = mesh_padded(
            padded,
            coord,
            classes,
            settings,
            &mut self.greedy,
            &mut self.nocubes,
            out,
        );
        if result.is_err() {
            out.clear();
        }
        result
    }
}

fn mesh_padded(
    padded: &PaddedChunk,
    coord: ChunkCoord,
    classes: &BlockClasses,
    settings: &MeshSettings,
    greedy: &mut GreedyMesher,
    nocubes: &mut Option<NoCubes>,
    out: &mut ChunkMesh,
) -> Result<(), MeshError> {
    match settings.surface {
        SurfaceMode::Greedy => greedy.mesh(padded, classes, &mut out.blocky)?,
        SurfaceMode::VisibleFaces => greedy.visible_faces(padded, classes, &mut out.blocky)?,
        SurfaceMode::NoCubes if classes.any_smoothable() => {
            nocubes.get_or_insert_with(NoCubes::new).mesh(
                padded,
                classes,
                &mut out.smooth,
                &mut out.blocky,
            )?;
        }
        SurfaceMode::NoCubes => greedy.mesh(padded, classes, &mut out.blocky)?,
    }
    if let Some(params) = &settings.clutter {
        place_clutter(padded, classes, coord, params, &mut out.clutter)?;
    }
    Ok(())
}

/// True when the chunk has no faces to mesh, known without gathering it: it is not stored (all
/// air), or it is uniform opaque and so are its six face neighbours.
pub(crate) fn is_trivially_empty<C: VoxelStorage>(
    world: &WorldMap<C>,
    coord: ChunkCoord,
    classes: &BlockClasses,
) -> bool {
    let Some(chunk) = world.get(coord) else {
        return true;
    };
    let uniform_opaque = |c: &C| c.uniform().is_some_and(|id| classes.is_opaque(id));
    uniform_opaque(chunk)
        && FaceDirection::ALL.iter().all(|face| {
            coord
                .checked_offset(face.normal())
                .ok()
                .and_then(|n| world.get(n))
                .is_some_and(uniform_opaque)
        })
}

/// Meshes `coords` one after another with one [`ChunkMesher`]; the `no_std` counterpart of
/// [`mesh_chunks`]. Stops at the first error.
pub fn mesh_chunks_sequential<C: VoxelStorage>(
    world: &WorldMap<C>,
    coords: &[ChunkCoord],
    classes: &BlockClasses,
    settings: &MeshSettings,
) -> Result<Vec<ChunkMesh>, MeshError> {
    let mut mesher = ChunkMesher::new();
    coords
        .iter()
        .map(|&coord| {
            let mut out = ChunkMesh::default();
            mesher
                .mesh_chunk(world, coord, classes, settings, &mut out)
                .map(|()| out)
        })
        .collect()
}

/// Meshes `coords` in parallel on rayon's current pool. The result is in the order of
/// `coords` and identical for any number of threads. Returns the first error in `coords` order.
///
/// Each worker thread keeps one [`ChunkMesher`] in a thread-local slot, so its scratch buffers
/// (a few hundred KB for 32^3 chunks) are allocated once per thread and reused by every later
/// call, not once per piece of work rayon splits off.
#[cfg(feature = "parallel")]
pub fn mesh_chunks<C: VoxelStorage + Sync>(
    world: &WorldMap<C>,
    coords: &[ChunkCoord],
    classes: &BlockClasses,
    settings: &MeshSettings,
) -> Result<Vec<ChunkMesh>, MeshError> {
    use core::cell::RefCell;
    use rayon::prelude::*;

    std::thread_local! {
        static MESHER: RefCell<ChunkMesher> = RefCell::new(ChunkMesher::new());
    }
    coords
        .par_iter()
        // One chunk per task: chunks cost from nothing (air, buried) to a few hundred µs, and
        // rayon's default split leaves runs of dozens of chunks that no idle thread can steal
        // from, so the last run keeps one thread busy while the others idle.
        .with_max_len(1)
        .map(|&coord| {
            let mut out = ChunkMesh::default();
            MESHER
                .with(|slot| match slot.try_borrow_mut() {
                    Ok(mut mesher) => mesher.mesh_chunk(world, coord, classes, settings, &mut out),
                    // Taken only if the storage itself waits on rayon while a chunk is meshed
                    // and this thread picks up another chunk meanwhile: a fresh mesher works.
                    Err(_) => {
                        ChunkMesher::new().mesh_chunk(world, coord, classes, settings, &mut out)
                    }
                })
                .map(|()| out)
        })
        .collect()
}
