//! Which geometry a node's opaque surface is drawn with ([`Geometry`]), and the per-node
//! comparison of the two ([`GeometryCounts`], [`geometry_counts`]).
//!
//! With [`Geometry::Shells`] a node keeps its transparent quads, its skirts (LOD borders) and
//! its far-draw data as they are; only its opaque greedy quads are replaced by the opaque
//! vertical runs of [`vertical_shells`](crate::vertical_shells) (the runs of transparent ids
//! are dropped: the transparent quads draw those voxels). At level `L` a run's voxels are
//! `2^L` blocks wide, like the quads'.
//!
//! With [`Geometry::Heightmap`] a node keeps only its transparent quads: its opaque surface is
//! the heightmap boxes of [`heightmap_boxes`](crate::heightmap::heightmap_boxes) (stored as
//! [`ShellRun`]s and drawn by the shell pass), whose border columns reach down as skirts, so
//! the node has no skirt quads; it has no far-draw data either (the boxes draw at every
//! distance).

use voxel_core::PaddedChunk;
use voxel_core::formats::{PackedQuad, ShellRun};

use crate::{BlockClasses, ChunkMesher, MeshError, MeshSettings, ShellRuns, SurfaceMode};

/// How a node's opaque blocky surface is extracted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Geometry {
    /// Opaque greedy quads, one per merged face ([`PackedQuad`], 8 bytes).
    #[default]
    Greedy,
    /// Opaque vertical shells, one box per run of exposed voxels ([`ShellRun`], 8 bytes),
    /// instead of the opaque greedy quads.
    Shells,
    /// Heightmap cubes (SBgl): one box per column of the top surface, split by block id
    /// ([`ShellRun`], 8 bytes), instead of the opaque quads, the skirts and the far-draw data.
    Heightmap,
}

/// Keeps the runs of `runs` that stand for opaque quads: opaque ids, minus the smoothable ones
/// that a NoCubes surface draws instead.
pub(crate) fn keep_opaque_runs(
    runs: &[ShellRun],
    classes: &BlockClasses,
    surface: SurfaceMode,
    out: &mut alloc::vec::Vec<ShellRun>,
) {
    let smooth = surface == SurfaceMode::NoCubes;
    out.extend(runs.iter().copied().filter(|run| {
        classes.class(run.block_id()).is_some_and(|class| {
            class.is_opaque() && !(smooth && class == voxel_core::MaterialClass::Smoothable)
        })
    }));
}

/// One node's opaque surface counted both ways: what [`Geometry::Greedy`] and
/// [`Geometry::Shells`] would upload for it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct GeometryCounts {
    /// Opaque greedy quads (skirts not included: both geometries keep them).
    pub quads: u64,
    /// Opaque shell runs.
    pub runs: u64,
}

impl GeometryCounts {
    /// Bytes of the opaque quads (8 each).
    pub fn quad_bytes(&self) -> u64 {
        self.quads * size_of::<PackedQuad>() as u64
    }

    /// Bytes of the shell runs (8 each).
    pub fn run_bytes(&self) -> u64 {
        self.runs * size_of::<ShellRun>() as u64
    }

    /// Triangles the greedy quads draw (2 per quad).
    pub fn quad_triangles(&self) -> u64 {
        self.quads * 2
    }

    /// Triangles the shells submit (6 per run, the 3 faces toward the eye; faces whose side bit is clear are
    /// degenerate and rasterise nothing).
    pub fn run_triangles(&self) -> u64 {
        self.runs * u64::from(ShellRun::VERTICES / 3)
    }
}

impl core::ops::Add for GeometryCounts {
    type Output = GeometryCounts;

    fn add(self, other: GeometryCounts) -> GeometryCounts {
        GeometryCounts {
            quads: self.quads + other.quads,
            runs: self.runs + other.runs,
        }
    }
}

/// Counts the opaque greedy quads and the opaque shell runs of the node whose padded
/// neighbourhood is `padded`, meshed with `mesh` (the benchmarks' per-node comparison of the
/// two geometries).
///
/// # Errors
///
/// [`MeshError::UnknownBlock`] for a voxel whose id has no material.
///
/// ```
/// use mesher::lod::geometry_counts;
/// use mesher::{BlockClasses, MeshSettings};
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(128, 128, 128))?;
/// let classes = BlockClasses::from_palette(&palette);
/// // Two separate pillars of 3 voxels: 2 runs, and 2 x 6 greedy quads.
/// let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     let pillar = (x == 2 || x == 5) && z == 3 && (1..=3).contains(&y);
///     if pillar { stone } else { BlockId::AIR }
/// });
/// let counts = geometry_counts(&chunk, &classes, &MeshSettings::default())?;
/// assert_eq!((counts.runs, counts.quads), (2, 12));
/// assert_eq!((counts.run_bytes(), counts.quad_bytes()), (16, 96));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn geometry_counts(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    mesh: &MeshSettings,
) -> Result<GeometryCounts, MeshError> {
    let mut mesher = ChunkMesher::new();
    let mut out = crate::ChunkMesh::default();
    let settings = MeshSettings {
        surface: mesh.surface,
        clutter: None,
    };
    mesher.mesh_gathered(padded, out.coord, classes, &settings, &mut out)?;
    let mut shells = ShellRuns::new();
    crate::vertical_shells(padded, classes, &mut shells)?;
    let mut opaque = alloc::vec::Vec::new();
    keep_opaque_runs(shells.runs(), classes, mesh.surface, &mut opaque);
    Ok(GeometryCounts {
        quads: out.blocky.opaque.len() as u64,
        runs: opaque.len() as u64,
    })
}
