//! The error type of the chunk storages and the world map.

use core::fmt;

use crate::{ChunkSize, CoordError};

/// A storage operation given a position, buffer or chunk that does not fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StorageError {
    /// A position outside the chunk.
    Coord(CoordError),
    /// A slice whose length does not match what the operation needs.
    WrongLength {
        /// The length required.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A chunk of another size than the world (or buffer) it is used with.
    SizeMismatch {
        /// The size required.
        expected: ChunkSize,
        /// The size given.
        got: ChunkSize,
    },
}

impl From<CoordError> for StorageError {
    fn from(value: CoordError) -> Self {
        StorageError::Coord(value)
    }
}

impl fmt::Display for StorageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StorageError::Coord(e) => e.fmt(f),
            StorageError::WrongLength { expected, got } => {
                write!(f, "slice of length {got} where {expected} is required")
            }
            StorageError::SizeMismatch { expected, got } => write!(
                f,
                "chunk of edge {} where edge {} is required",
                got.edge(),
                expected.edge()
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for StorageError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            StorageError::Coord(e) => Some(e),
            _ => None,
        }
    }
}
