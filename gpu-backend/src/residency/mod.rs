//! Residency: the nodes (level-0 chunks and coarser level-of-detail nodes) on the GPU, apart
//! from the passes that draw them.
//!
//! ```text
//!  upload(ChunkMeshData) ─► Gigabuffer (quads, smooth vertices, smooth quads, clutter, draw
//!                  │        blocks: one paged buffer per kind, sub-allocated per node)
//!                  ├──────► MeshedChunkTable (MeshedChunkInfo per slot: bounds, layer ranges)
//!                  └──────► node table (NodeRecord per slot: smooth quads, blocks, skirts)
//!  flush(encoder)  ─► the frame's copies and table writes, before any pass reads them
//!  free(handle)    ─► the space and the slot back
//! ```
//!
//! [`Residency`] owns the [`gigabuffer`] and the [`chunk_table`]s and keeps both tables in the
//! same slots: slot `s` of the chunk table and of the node table describe one node. The cull
//! pass reads both; every pass that draws reads the gigabuffer's pages. What a node records is
//! decided by `render_model::resident` (bounds, chunk record) and `render_model::cull`
//! (`NodeRecord`); the memory rule that decides which nodes to keep is
//! `render_model::memory_plan`.

pub mod chunk_table;
mod error;
pub mod gigabuffer;

use std::collections::HashMap;

use render_model::cull::NodeRecord;
use render_model::resident::{
    ChunkMeshData, ChunkRanges, SmoothFrame, SmoothRanges, chunk_record, mesh_bounds,
};
use voxel_core::ChunkSize;
use voxel_core::FormatError;
use voxel_core::formats::{ChunkLayersData, DataKind, DrawBlock, MeshedChunkInfo, ShellRun};
use wgpu::{CommandEncoder, Device, Queue};

pub use chunk_table::{FarChunkTable, GpuTable, MeshedChunkTable, TableError, TableSlot};
pub use error::ResidencyError;
pub use gigabuffer::{
    ChunkHandle, FlushStats, Gigabuffer, GigabufferConfig, GigabufferError, KindUsage,
    ResidentReport, UploadedChunk,
};

use crate::device::GpuCapabilities;

/// How a [`Residency`] is sized.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResidencyConfig<'a> {
    /// Edge of every node.
    pub chunk_size: ChunkSize,
    /// Gigabuffer budget per kind.
    pub gigabuffer: &'a GigabufferConfig,
    /// Resident nodes at most (the tables' capacity).
    pub max_chunks: u32,
    /// How smooth vertex positions map to node-local blocks (their bounds).
    pub smooth: SmoothFrame,
}

/// A resident node.
#[derive(Debug)]
struct Resident {
    slot: TableSlot,
    level: u32,
    smooth: Option<SmoothRanges>,
}

/// The resident nodes: their data, their records and their counts (see the
/// [module docs](self)).
#[derive(Debug)]
pub struct Residency {
    gigabuffer: Gigabuffer,
    table: MeshedChunkTable,
    /// Per table slot, what the chunk record does not hold (same slots as `table`).
    nodes: GpuTable<NodeRecord>,
    chunks: HashMap<ChunkHandle, Resident>,
    /// Resident nodes per level of detail (the top level is the highest with any).
    per_level: [u32; 16],
    /// Resident nodes with a smooth layer.
    smooth_chunks: u32,
    chunk_size: ChunkSize,
    smooth: SmoothFrame,
    /// Uploads and frees so far (see [`Residency::changes`]).
    changes: u64,
}

impl Residency {
    /// An empty residency on `device`: no GPU memory for node data is taken until the first
    /// upload of each kind; the tables are created at their full capacity.
    pub fn new(
        device: &Device,
        capabilities: &GpuCapabilities,
        config: &ResidencyConfig<'_>,
    ) -> Result<Residency, ResidencyError> {
        let gigabuffer = Gigabuffer::new(device, capabilities, config.gigabuffer)?;
        let max_binding = capabilities.max_storage_buffer_binding_size;
        let table = MeshedChunkTable::new(device, config.max_chunks, max_binding)?;
        let nodes = GpuTable::new(device, config.max_chunks, max_binding)?;
        Ok(Residency {
            gigabuffer,
            table,
            nodes,
            chunks: HashMap::new(),
            per_level: [0; 16],
            smooth_chunks: 0,
            chunk_size: config.chunk_size,
            smooth: config.smooth,
            changes: 0,
        })
    }

    /// The gigabuffer (pages, layouts, memory use).
    pub fn gigabuffer(&self) -> &Gigabuffer {
        &self.gigabuffer
    }

    /// The chunk table (`MeshedChunkInfo` per slot).
    pub fn table(&self) -> &MeshedChunkTable {
        &self.table
    }

    /// The node table (`NodeRecord` per slot, the chunk table's slots).
    pub fn nodes(&self) -> &GpuTable<NodeRecord> {
        &self.nodes
    }

    /// Resident nodes.
    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// Resident nodes per level of detail.
    pub fn chunks_per_level(&self) -> [u32; 16] {
        self.per_level
    }

    /// The highest level of detail any resident node has (0 when none is resident).
    pub fn top_level(&self) -> u32 {
        self.per_level.iter().rposition(|&n| n > 0).unwrap_or(0) as u32
    }

    /// True when a resident node has a smooth layer.
    pub fn has_smooth(&self) -> bool {
        self.smooth_chunks > 0
    }

    /// Smooth quads of the resident nodes.
    pub fn smooth_quad_count(&self) -> u64 {
        self.chunks
            .values()
            .filter_map(|r| r.smooth)
            .map(|s| u64::from(s.quad_count))
            .sum()
    }

    /// GPU bytes of node data and records, by kind: the gigabuffer's used bytes per data kind,
    /// then the chunk and node tables.
    pub fn resident_bytes(&self) -> Vec<(&'static str, u64)> {
        let used = self.gigabuffer.resident();
        let mut out: Vec<(&'static str, u64)> = DataKind::ALL
            .iter()
            .map(|&kind| (kind.name(), used.kinds.get(kind).used_bytes))
            .collect();
        out.push(("chunk table", self.table.buffer().size()));
        out.push(("node table", self.nodes.buffer().size()));
        out
    }

    /// Uploads and frees so far: two equal counts mean the same resident nodes with the same
    /// data, so a pass that derives data from them (the shadow grid) may keep what it made.
    pub fn changes(&self) -> u64 {
        self.changes
    }

    /// Uploads a node's mesh (its bytes reach the GPU with the next [`flush`](Self::flush))
    /// and returns its handle. On error nothing stays allocated.
    pub fn upload(&mut self, mesh: &ChunkMeshData<'_>) -> Result<ChunkHandle, ResidencyError> {
        if mesh.lod > MeshedChunkInfo::MAX_LOD {
            return Err(ResidencyError::BadLevel(mesh.lod));
        }
        check_far_data(self.chunk_size, &mesh.layers)?;
        check_shell_runs(self.chunk_size, mesh.layers.shell_runs)?;
        let bounds = mesh_bounds(&mesh.layers, self.smooth);
        let uploaded = self.gigabuffer.upload(&mesh.layers)?;
        let slot = match self.insert_records(mesh, bounds, &uploaded.ranges) {
            Ok(slot) => slot,
            Err(e) => {
                // The upload succeeded; give its space back before reporting.
                self.gigabuffer.free(uploaded.handle)?;
                return Err(e);
            }
        };
        let ranges = uploaded.ranges;
        let smooth = (ranges.smooth_quad_count > 0).then_some(SmoothRanges {
            vertices: ranges.smooth_vertices,
            quads: ranges.smooth_quads,
            quad_count: ranges.smooth_quad_count,
            form: ranges.smooth_quad_form,
        });
        self.per_level[mesh.lod as usize] += 1;
        self.smooth_chunks += u32::from(smooth.is_some());
        self.chunks.insert(
            uploaded.handle,
            Resident {
                slot,
                level: mesh.lod,
                smooth,
            },
        );
        self.changes += 1;
        Ok(uploaded.handle)
    }

    /// The chunk and node records of an uploaded node, in the same slot of both tables.
    fn insert_records(
        &mut self,
        mesh: &ChunkMeshData<'_>,
        bounds: Option<([f32; 3], [f32; 3])>,
        ranges: &ChunkRanges,
    ) -> Result<TableSlot, ResidencyError> {
        let record = chunk_record(mesh.coord, mesh.lod, bounds, ranges)?;
        let node = NodeRecord::new(ranges)?;
        let slot = self.table.insert(record)?;
        match self.nodes.insert(node) {
            // Both tables hand out the lowest free slot and change together, so they agree.
            Ok(node_slot) if node_slot == slot => Ok(slot),
            Ok(node_slot) => {
                self.nodes.remove(node_slot)?;
                self.table.remove(slot)?;
                Err(ResidencyError::Table(TableError::VacantSlot(node_slot)))
            }
            Err(e) => {
                self.table.remove(slot)?;
                Err(e.into())
            }
        }
    }

    /// Frees a resident node: its space and table slot. A stale or foreign handle is an error
    /// and frees nothing.
    pub fn free(&mut self, handle: ChunkHandle) -> Result<(), ResidencyError> {
        let resident = self
            .chunks
            .remove(&handle)
            .ok_or(ResidencyError::UnknownChunk(handle))?;
        self.per_level[resident.level as usize] -= 1;
        self.smooth_chunks -= u32::from(resident.smooth.is_some());
        self.table.remove(resident.slot)?;
        self.nodes.remove(resident.slot)?;
        self.gigabuffer.free(handle)?;
        self.changes += 1;
        Ok(())
    }

    /// Records the pending gigabuffer copies into `encoder` and writes the changed table slots
    /// through `queue`: what the passes of a frame read comes first in its submission. When the
    /// device refuses the staging buffer, nothing is sent and the uploads stay pending.
    pub fn flush(
        &mut self,
        encoder: &mut CommandEncoder,
        queue: &Queue,
    ) -> Result<(), ResidencyError> {
        self.gigabuffer.flush(encoder)?;
        self.table.flush(queue);
        self.nodes.flush(queue);
        Ok(())
    }
}

/// Far-draw data must come whole: blocks with the hiding mask of the node's padded
/// neighbourhood, in nodes a `DrawBlock` can address.
/// Every run of `runs` decodes and its box lies inside a chunk of `size`: the shell pass draws each
/// one's box, whatever its bytes, so a bad run is refused here, by name.
fn check_shell_runs(size: ChunkSize, runs: &[ShellRun]) -> Result<(), ResidencyError> {
    let edge = i64::from(size.edge());
    let inside = |field, value: u32, max: i64| {
        if i64::from(value) <= max {
            Ok(())
        } else {
            Err(FormatError::IntegerOutOfRange {
                field,
                value: value.into(),
                min: 0,
                max,
            })
        }
    };
    for (index, run) in runs.iter().enumerate() {
        let checked = run.decode().and_then(|f| {
            let [x, y, z] = f.position;
            inside("ShellRun.x", x, edge - 1)?;
            inside("ShellRun.z", z, edge - 1)?;
            inside("ShellRun.x + width", x + f.width, edge)?;
            inside("ShellRun.y + height", y + f.height, edge)
        });
        checked.map_err(|error| ResidencyError::BadShellRun { run: index, error })?;
    }
    Ok(())
}

fn check_far_data(size: ChunkSize, layers: &ChunkLayersData<'_>) -> Result<(), ResidencyError> {
    let blocks = layers.draw_blocks.len()
        + layers
            .draw_block_skirts
            .iter()
            .map(|s| s.len())
            .sum::<usize>();
    if blocks == 0 && layers.hiding_mask.is_empty() && layers.transparent_mask.is_empty() {
        return Ok(());
    }
    let edge = size.edge();
    if edge > DrawBlock::MAX_POSITION + 1 {
        return Err(ResidencyError::BadFarData(format!(
            "chunks of edge {edge} have draw blocks, but a DrawBlock addresses 16^3: far draws \
             need chunks of at most 16^3"
        )));
    }
    let p = (edge + 2) as usize;
    let words = (p * p * p).div_ceil(32);
    if layers.hiding_mask.len() != words {
        return Err(ResidencyError::BadFarData(format!(
            "{blocks} draw blocks come with a hiding mask of {} words; chunks of edge {edge} \
             need {words} (mesher::surface_blocks::hiding_mask)",
            layers.hiding_mask.len()
        )));
    }
    if !layers.transparent_mask.is_empty() && layers.transparent_mask.len() != words {
        return Err(ResidencyError::BadFarData(format!(
            "a transparent mask of {} words; chunks of edge {edge} need {words} or none \
             (mesher::surface_blocks::transparent_mask)",
            layers.transparent_mask.len()
        )));
    }
    Ok(())
}
