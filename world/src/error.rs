//! [`WorldError`]: every way a world operation fails, by name.

use core::fmt;
use std::path::PathBuf;

use voxel_core::ChunkCoord;

use crate::{EditError, RegionFormatError};

/// Why a world operation fails.
#[derive(Debug)]
pub enum WorldError {
    /// An edit of the batch is refused (nothing of the batch is written).
    Edit(EditError),
    /// The base could not produce a chunk.
    Base {
        /// The chunk.
        coord: ChunkCoord,
        /// The base's message.
        message: String,
    },
    /// A level past [`MAX_LEVEL`](crate::MAX_LEVEL).
    BadLevel {
        /// The level asked for.
        level: u32,
    },
    /// Downsampling a level-of-detail node failed (a block id the classes do not know).
    Mesh {
        /// The node's level.
        level: u32,
        /// The node.
        coord: ChunkCoord,
        /// The mesher's error.
        error: mesher::MeshError,
    },
    /// The world is asked for its base's own levels, and the base has none.
    NoBaseLevels,
    /// Reading or writing a file failed.
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        error: std::io::Error,
    },
    /// A region file is refused whole.
    Region {
        /// The file.
        path: PathBuf,
        /// Why.
        error: RegionFormatError,
    },
    /// The folder's world file is missing, refused, or names another chunk size.
    WorldFile {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
}

impl fmt::Display for WorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WorldError::Edit(e) => write!(f, "edit refused: {e}"),
            WorldError::Base { coord, message } => write!(
                f,
                "base chunk ({}, {}, {}): {message}",
                coord.x, coord.y, coord.z
            ),
            WorldError::NoBaseLevels => write!(
                f,
                "the base has no coarse levels of its own (only the terrain has them)"
            ),
            WorldError::BadLevel { level } => {
                write!(
                    f,
                    "level {level} is past the highest level {}",
                    crate::MAX_LEVEL
                )
            }
            WorldError::Mesh {
                level,
                coord,
                error,
            } => write!(
                f,
                "downsampling node ({}, {}, {}) of level {level}: {error}",
                coord.x, coord.y, coord.z
            ),
            WorldError::Io { path, error } => write!(f, "{}: {error}", path.display()),
            WorldError::Region { path, error } => {
                write!(f, "region file {} refused: {error}", path.display())
            }
            WorldError::WorldFile { path, reason } => {
                write!(f, "world file {} refused: {reason}", path.display())
            }
        }
    }
}

impl std::error::Error for WorldError {}
