//! CPU meshing figures: time per chunk (median of N runs, one thread), quads, triangles and
//! bytes for every mesher mode and chunk size, on the `.vox` samples and the procedural terrain.

use std::time::Instant;

use mesher::{BlockClasses, MeshSettings, SurfaceMode, mesh_chunks_sequential};
use voxel_core::storage::{PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{ChunkCoord, ChunkSize, MaterialPalette};
use voxel_scene::vox::{VoxOptions, load_vox_file_with};

use super::{Config, ReportError};

/// Most voxels a sample model may hold (a guard, far above the samples).
const MAX_VOX_VOXELS: usize = 1 << 28;

/// The mesher modes the report compares.
pub const MODES: [(SurfaceMode, &str); 3] = [
    (SurfaceMode::VisibleFaces, "faces"),
    (SurfaceMode::Greedy, "greedy"),
    (SurfaceMode::NoCubes, "smooth"),
];

/// The figures of one input meshed in one mode at one chunk size.
#[derive(Clone, Debug, PartialEq)]
pub struct CpuRow {
    /// The input's name (a model's file stem, or `terrain SIDE²`).
    pub input: String,
    /// The mode's name (`faces`, `greedy`, `smooth`).
    pub mode: &'static str,
    /// Chunk edge in voxels.
    pub chunk_edge: u32,
    /// Chunks stored (not all air), all of them meshed.
    pub chunks: usize,
    /// Non-air voxels of the input.
    pub voxels: usize,
    /// Median wall time of meshing every chunk once, one thread, in seconds.
    pub seconds: f64,
    /// Quads of every layer (greedy or face quads plus smooth quads).
    pub quads: usize,
    /// Triangles drawn: two per quad.
    pub triangles: usize,
    /// Packed GPU bytes of every layer ([`mesher::ChunkMesh::byte_len`]).
    pub bytes: usize,
}

impl CpuRow {
    /// Median time per stored chunk, in microseconds.
    pub fn micros_per_chunk(&self) -> f64 {
        self.seconds * 1e6 / self.chunks.max(1) as f64
    }

    /// Median time per million non-air voxels, in milliseconds.
    pub fn millis_per_mvoxel(&self) -> f64 {
        self.seconds * 1e3 * 1e6 / self.voxels.max(1) as f64
    }

    /// Bytes per non-air voxel.
    pub fn bytes_per_voxel(&self) -> f64 {
        self.bytes as f64 / self.voxels.max(1) as f64
    }
}

/// A world to mesh and its materials.
#[derive(Debug)]
pub struct Input {
    /// Name in the tables.
    pub name: String,
    /// The voxels.
    pub world: WorldMap<PaletteChunk>,
    /// The materials of the ids in `world`.
    pub palette: MaterialPalette,
}

/// Loads every input of `config` at chunk size `size`.
pub fn load_inputs(config: &Config, size: ChunkSize) -> Result<Vec<Input>, ReportError> {
    let mut inputs = Vec::new();
    if config.terrain_side > 0 {
        let t = voxel_scene::terrain_columns(config.terrain_seed, size, config.terrain_side);
        inputs.push(Input {
            name: format!("terrain {0}x{0}", config.terrain_side),
            world: t.world,
            palette: t.palette,
        });
    }
    for path in &config.vox_files {
        let vox = load_vox_file_with(path, &VoxOptions::new(size, MAX_VOX_VOXELS))
            .map_err(|e| ReportError(format!("{}: {e}", path.display())))?;
        let name = path.file_stem().map_or_else(
            || path.display().to_string(),
            |s| s.to_string_lossy().into(),
        );
        inputs.push(Input {
            name,
            world: vox.world,
            palette: vox.palette,
        });
    }
    Ok(inputs)
}

/// The classes the mesher sees in `mode`: for the smooth mode every opaque material is made
/// smoothable (so the whole input is smoothed, as `voxmesh --mode smooth` does); otherwise the
/// palette's own classes.
pub fn classes_for(palette: &MaterialPalette, mode: SurfaceMode) -> BlockClasses {
    if mode != SurfaceMode::NoCubes {
        return BlockClasses::from_palette(palette);
    }
    BlockClasses::all_opaque_smoothable(palette)
}

/// Meshes `input` in `mode` `runs` times on this thread; the median time and the mesh sizes.
pub fn mesh_input(
    input: &Input,
    mode: (SurfaceMode, &'static str),
    runs: usize,
) -> Result<CpuRow, ReportError> {
    let mut coords: Vec<ChunkCoord> = input.world.iter().map(|(c, _)| c).collect();
    coords.sort_unstable();
    let voxels = input.world.iter().map(|(_, c)| c.non_air_count()).sum();
    let classes = classes_for(&input.palette, mode.0);
    let settings = MeshSettings {
        surface: mode.0,
        clutter: None,
    };
    let mut times = Vec::with_capacity(runs.max(1));
    let mut sizes = (0, 0);
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        let meshes = mesh_chunks_sequential(&input.world, &coords, &classes, &settings)
            .map_err(|e| ReportError(format!("{} ({}): {e}", input.name, mode.1)))?;
        times.push(start.elapsed().as_secs_f64());
        let quads = meshes
            .iter()
            .map(|m| m.blocky.len() + m.smooth.quad_count())
            .sum();
        let bytes = meshes.iter().map(mesher::ChunkMesh::byte_len).sum();
        sizes = (quads, bytes);
    }
    Ok(CpuRow {
        input: input.name.clone(),
        mode: mode.1,
        chunk_edge: input.world.size().edge(),
        chunks: coords.len(),
        voxels,
        seconds: median(&mut times),
        quads: sizes.0,
        triangles: sizes.0 * 2,
        bytes: sizes.1,
    })
}

/// Every input of `config` in every mode at every chunk size.
pub fn measure(config: &Config, progress: &dyn Fn(&str)) -> Result<Vec<CpuRow>, ReportError> {
    let mut rows = Vec::new();
    for &size in &config.chunk_sizes {
        for input in load_inputs(config, size)? {
            for mode in MODES {
                progress(&format!("  {} {} {}^3", input.name, mode.1, size.edge()));
                rows.push(mesh_input(&input, mode, config.runs)?);
            }
        }
    }
    Ok(rows)
}

/// The median of `values` (sorts them); 0 for none.
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}
