//! Why an upload or a free was refused.

use std::fmt;

use render_model::cull::SkirtTooLarge;
use voxel_core::FormatError;

use super::chunk_table::TableError;
use super::gigabuffer::{ChunkHandle, GigabufferError};

/// An error of [`Residency`](super::Residency): each names the problem, none is a panic. A
/// refused upload leaves nothing allocated.
#[derive(Debug)]
#[non_exhaustive]
pub enum ResidencyError {
    /// The gigabuffer refused an upload or free (out of space, a layer larger than a page, a
    /// page the device refused, ...).
    Gigabuffer(GigabufferError),
    /// The chunk table is full or the slot is stale.
    Table(TableError),
    /// A chunk record does not encode (non-finite bounds, range overflow).
    Format(FormatError),
    /// A chunk has more skirt elements on one side than a node records.
    Skirt(SkirtTooLarge),
    /// A handle that names no resident chunk.
    UnknownChunk(ChunkHandle),
    /// A chunk's level of detail is above 15 (`MeshedChunkInfo::MAX_LOD`).
    BadLevel(u32),
    /// A chunk's far-draw data does not fit (what is wrong, in words).
    BadFarData(String),
    /// A chunk's shell run does not decode (a height of 0, a run past 64 voxels, empty side
    /// bits, a set reserved byte) or leaves the chunk; `error` names the field.
    BadShellRun {
        /// The run's index in the chunk's shell runs.
        run: usize,
        /// What is wrong with it.
        error: FormatError,
    },
}

impl ResidencyError {
    /// True when the upload failed for want of GPU memory: the gigabuffer or the chunk table
    /// is full, or the device refused a page. A streaming caller coarsens its view.
    pub fn is_out_of_memory(&self) -> bool {
        matches!(
            self,
            ResidencyError::Gigabuffer(
                GigabufferError::OutOfMemory { .. }
                    | GigabufferError::TooManyChunks { .. }
                    | GigabufferError::PageCreation { .. }
            ) | ResidencyError::Table(TableError::Full { .. })
        )
    }
}

impl fmt::Display for ResidencyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ResidencyError::Gigabuffer(e) => write!(f, "gigabuffer: {e}"),
            ResidencyError::Table(e) => write!(f, "chunk table: {e}"),
            ResidencyError::Format(e) => write!(f, "chunk record: {e}"),
            ResidencyError::Skirt(e) => write!(f, "skirts: {e}"),
            ResidencyError::UnknownChunk(h) => {
                write!(f, "chunk handle {h:?} names no resident chunk")
            }
            ResidencyError::BadLevel(level) => {
                write!(f, "chunk level of detail {level} is above the largest, 15")
            }
            ResidencyError::BadFarData(why) => write!(f, "far-draw data: {why}"),
            ResidencyError::BadShellRun { run, error } => write!(f, "shell run {run}: {error}"),
        }
    }
}

impl std::error::Error for ResidencyError {}

impl From<GigabufferError> for ResidencyError {
    fn from(e: GigabufferError) -> Self {
        ResidencyError::Gigabuffer(e)
    }
}

impl From<TableError> for ResidencyError {
    fn from(e: TableError) -> Self {
        ResidencyError::Table(e)
    }
}

impl From<FormatError> for ResidencyError {
    fn from(e: FormatError) -> Self {
        ResidencyError::Format(e)
    }
}

impl From<SkirtTooLarge> for ResidencyError {
    fn from(e: SkirtTooLarge) -> Self {
        ResidencyError::Skirt(e)
    }
}
