//! MagicaVoxel `.vox` scenes: every model the scene graph shows, with its transforms, and the
//! palette and materials.
//!
//! # What is loaded
//!
//! - **Models and the scene graph.** With a scene graph (`nTRN`, `nGRP`, `nSHP` chunks), every
//!   shape reachable from root node 0 is drawn with its transforms (rotation `_r` and
//!   translation `_t` of each transform's first frame, composed from the root down); each
//!   model is centred on its translation as MagicaVoxel does (see `Transform::place_voxel`).
//!   Nodes marked `_hidden` and transforms on a hidden layer (`LAYR` with `_hidden` = `1`) are
//!   left out with everything below them, unless [`VoxOptions::include_hidden`]. A layer id
//!   without a `LAYR` chunk is a visible layer (no attributes). Without a scene graph, model 0
//!   is drawn with its corner at the origin: several models without a graph are the frames of
//!   an animation. Only the first frame of an animation is drawn; [`LoadReport`] says when
//!   there were more.
//! - **Axes.** MagicaVoxel is right-handed with z up; this project is right-handed with y up.
//!   A voxel at file position `(x, y, z)` lands at world `(x, z, -1 - y)`.
//! - **Colours.** Colour index `i` (1..=255) becomes block id `i`. [`VoxScene::materials`] holds
//!   each index's colour (the `RGBA` chunk, or MagicaVoxel's default palette) and material
//!   (`MATL`, or the older `MATT`; see [`materials`]); [`VoxScene::palette`]
//!   is the same as the renderer's [`MaterialPalette`].
//! - **Overlaps.** Where models overlap, the one drawn later (scene-graph order) wins;
//!   [`LoadReport::overwritten_voxels`] counts the voxels that were covered.
//! - **Repeated voxels.** Where one model lists two voxels at one position, the later one in
//!   the file wins, as in MagicaVoxel (whose models are dense grids filled in file order; see
//!   `chunks::voxels` for the evidence); [`LoadReport::repeated_voxels`] counts the voxels
//!   replaced.
//! - **Other chunks.** MagicaVoxel's renderer settings, palette notes and palette display
//!   order are skipped; a chunk id nobody knows is skipped too and listed in
//!   [`LoadReport::unknown_chunks`]. A material for the palette's unused 256th entry (id 256,
//!   which some MagicaVoxel versions write) is accepted and not used.
//!
//! # What is refused
//!
//! This loader is strict: MagicaVoxel would not write any of these, and each is a
//! [`VoxError`] that says what is wrong and where (chunk id and byte offset, model index,
//! voxel position, scene node): a file cut short (in any chunk or header) or with bytes after
//! `MAIN`; a chunk longer or shorter than its fields; a model size of 0, negative or over 256;
//! a voxel count that does not match the chunk; a voxel outside its model or with colour
//! index 0; no model at all; a `PACK` count that differs from the models;
//! `SIZE` and `XYZI` chunks out of pairs; a second definition of a node, layer, material,
//! palette or `PACK`; duplicate dictionary keys; scene nodes referring to missing nodes or
//! models, a missing root, a node reached twice (cycles included), a graph deeper than
//! [`MAX_SCENE_DEPTH`]; rotations, translations, hidden flags or material values that do not
//! parse or are out of range; voxels placed outside the i32 world; more voxels than allowed.
//!
//! The `dot_vox` crate is not used to parse: it skips malformed chunks without a word (an
//! unreadable node or model simply disappears), reads colour index 0 as 1, indexes scene
//! nodes by file order instead of by id, and reports errors without a place. The parser here
//! is small (`reader` for the framing, `chunks` for the contents) and the tests cross-check
//! it against `dot_vox` on valid files.

mod chunks;
mod error;
mod graph;
pub mod materials;
mod reader;
mod transform;

use std::path::Path;

use voxel_core::storage::{PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{BlockId, ChunkSize, MaterialPalette, WorldPos};

pub use error::{ChunkAt, ChunkId, VoxError};
pub use materials::{VoxMaterial, VoxMaterialKind};

/// Deepest scene graph the loader follows.
pub const MAX_SCENE_DEPTH: usize = 64;

/// How to load a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VoxOptions {
    /// Chunk edge of the world the voxels are stored in.
    pub chunk_size: ChunkSize,
    /// Most voxels the scene may place (a guard against files that would exhaust memory).
    pub max_voxels: usize,
    /// Draw hidden nodes and hidden layers too.
    pub include_hidden: bool,
}

impl VoxOptions {
    /// Chunks of `chunk_size`, at most `max_voxels` voxels, hidden nodes and layers left out.
    pub fn new(chunk_size: ChunkSize, max_voxels: usize) -> VoxOptions {
        VoxOptions {
            chunk_size,
            max_voxels,
            include_hidden: false,
        }
    }
}

/// What the loader left out or changed, for the user to be told.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LoadReport {
    /// Models in the file.
    pub models: usize,
    /// Models drawn at least once.
    pub models_drawn: usize,
    /// Scene nodes left out because they or their layer are hidden.
    pub hidden_nodes: usize,
    /// Of those, nodes left out because their layer is hidden.
    pub hidden_by_layer: usize,
    /// True when the file holds animation frames after the first (not drawn).
    pub animated: bool,
    /// Voxels covered by a later model at the same position.
    pub overwritten_voxels: usize,
    /// Voxels of a model replaced by a later voxel of the same model at the same position
    /// (the later one is drawn).
    pub repeated_voxels: usize,
    /// Chunks skipped because their id is not known (id and offset).
    pub unknown_chunks: Vec<ChunkAt>,
    /// Material types not known here (colour index and `_type`), drawn as diffuse.
    pub unknown_material_types: Vec<(u8, String)>,
    /// Colour indices whose emission (`_emit * (1 + _flux)`) is above 1, which the
    /// renderer's material holds at most ([`VoxMaterial::to_material`]): drawn at full
    /// strength.
    pub saturated_emission: Vec<u8>,
}

impl LoadReport {
    /// One line per thing the user should know, empty when the file was drawn as it is.
    pub fn notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        if self.hidden_nodes > 0 {
            notes.push(format!(
                "{} hidden scene nodes left out ({} of them on hidden layers); --hidden includes them",
                self.hidden_nodes, self.hidden_by_layer
            ));
        }
        if self.animated {
            notes.push("the file is animated: only the first frame is drawn".to_owned());
        }
        let undrawn = self.models - self.models_drawn;
        if undrawn > 0 && !self.animated {
            notes.push(format!(
                "{undrawn} of {} models are not drawn (hidden or not in the scene graph)",
                self.models
            ));
        }
        if self.repeated_voxels > 0 {
            notes.push(format!(
                "{} voxels repeat a position within their model; the later one in the file is \
                 drawn, as in MagicaVoxel",
                self.repeated_voxels
            ));
        }
        if self.overwritten_voxels > 0 {
            notes.push(format!(
                "models overlap: {} voxels are covered by a later model",
                self.overwritten_voxels
            ));
        }
        for chunk in &self.unknown_chunks {
            notes.push(format!("{chunk} has an unknown id and was skipped"));
        }
        for (index, kind) in &self.unknown_material_types {
            notes.push(format!(
                "material {index} has the unknown type {kind:?} and is drawn as diffuse"
            ));
        }
        if !self.saturated_emission.is_empty() {
            notes.push(format!(
                "materials {:?} emit more than the renderer's brightest emission (1) and are \
                 drawn at it",
                self.saturated_emission
            ));
        }
        notes
    }
}

/// A loaded `.vox` file.
#[derive(Debug)]
pub struct VoxScene {
    /// The voxels, in chunks of [`VoxOptions::chunk_size`].
    pub world: WorldMap<PaletteChunk>,
    /// Block id `i` is the file's colour index `i` (1..=255).
    pub palette: MaterialPalette,
    /// The material of every colour index (0..=255; index 0 is empty space).
    pub materials: Vec<VoxMaterial>,
    /// Smallest and largest occupied world position (inclusive); `None` when nothing is drawn
    /// (every model hidden).
    pub bounds: Option<(WorldPos, WorldPos)>,
    /// Occupied voxels in `world`.
    pub voxel_count: usize,
    /// The file's version number (150 or 200 from MagicaVoxel).
    pub version: u32,
    /// What was left out or changed.
    pub report: LoadReport,
}

/// Loads a `.vox` file into chunks of `size`, refusing scenes of more than `max_voxels`;
/// hidden nodes and layers are left out.
pub fn load_vox_file(
    path: &Path,
    size: ChunkSize,
    max_voxels: usize,
) -> Result<VoxScene, VoxError> {
    load_vox_file_with(path, &VoxOptions::new(size, max_voxels))
}

/// Loads a `.vox` file with `options`.
pub fn load_vox_file_with(path: &Path, options: &VoxOptions) -> Result<VoxScene, VoxError> {
    let bytes = std::fs::read(path).map_err(VoxError::Read)?;
    load_vox_with(&bytes, options)
}

/// Loads `.vox` bytes into chunks of `size`, refusing scenes of more than `max_voxels`;
/// hidden nodes and layers are left out.
pub fn load_vox_bytes(
    bytes: &[u8],
    size: ChunkSize,
    max_voxels: usize,
) -> Result<VoxScene, VoxError> {
    load_vox_with(bytes, &VoxOptions::new(size, max_voxels))
}

/// Loads `.vox` bytes with `options`.
pub fn load_vox_with(bytes: &[u8], options: &VoxOptions) -> Result<VoxScene, VoxError> {
    let (version, chunks) = reader::read_chunks(bytes)?;
    let file = chunks::parse(&chunks)?;
    let materials::Materials {
        by_index: materials,
        unknown_types: unknown_material_types,
    } = materials::materials_of(&file)?;
    let walk = graph::walk(&file, options.include_hidden)?;

    let mut world: WorldMap<PaletteChunk> = WorldMap::new(options.chunk_size);
    let mut bounds: Option<(WorldPos, WorldPos)> = None;
    let (mut written, mut overwritten) = (0usize, 0usize);
    for placement in &walk.placements {
        let model = &file.models[placement.model];
        for &[x, y, z, index] in &model.voxels {
            let [fx, fy, fz] = if placement.centred {
                placement.transform.place_voxel([x, y, z], model.size)
            } else {
                [x, y, z].map(i64::from)
            };
            // z-up file axes to y-up world axes.
            let world_pos = [fx, fz, -1 - fy].map(i32::try_from);
            let [Ok(wx), Ok(wy), Ok(wz)] = world_pos else {
                return Err(VoxError::OutOfWorld {
                    model: placement.model,
                    position: [x, y, z],
                });
            };
            if written >= options.max_voxels {
                return Err(VoxError::TooManyVoxels {
                    limit: options.max_voxels,
                });
            }
            written += 1;
            let pos = WorldPos::new(wx, wy, wz);
            if !world.set_block(pos, BlockId(u16::from(index))).is_air() {
                overwritten += 1;
            }
            bounds = Some(match bounds {
                None => (pos, pos),
                Some((lo, hi)) => (
                    WorldPos::new(lo.x.min(wx), lo.y.min(wy), lo.z.min(wz)),
                    WorldPos::new(hi.x.max(wx), hi.y.max(wy), hi.z.max(wz)),
                ),
            });
        }
    }
    let voxel_count = world.iter().map(|(_, c)| c.non_air_count()).sum();
    debug_assert_eq!(voxel_count, written - overwritten);
    let report = LoadReport {
        models: file.models.len(),
        models_drawn: file.models.len() - walk.unplaced_models,
        hidden_nodes: walk.hidden_nodes,
        hidden_by_layer: walk.hidden_by_layer,
        animated: walk.animated,
        overwritten_voxels: overwritten,
        repeated_voxels: file.models.iter().map(|m| m.repeated).sum(),
        unknown_chunks: file.unknown,
        unknown_material_types,
        saturated_emission: (1..=255u8)
            .filter(|&i| materials[usize::from(i)].emission > 1.0)
            .collect(),
    };
    Ok(VoxScene {
        world,
        palette: materials::palette_of(&materials),
        materials,
        bounds,
        voxel_count,
        version,
        report,
    })
}
