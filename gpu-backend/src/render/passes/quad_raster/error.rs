//! Why the quad rasteriser refused something.

use std::fmt;

use crate::device::alloc::AllocError;

/// An error of [`QuadRaster`](super::QuadRaster): each names the problem, none is a panic.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum QuadRasterError {
    /// The device was created without `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX`
    /// (`GpuCapabilities::int64_atomics`).
    MissingInt64Atomics,
    /// A list would not fit one storage binding of the device, or its capacity is 0.
    BadCapacity {
        /// Which list.
        list: &'static str,
        /// Bytes it would take.
        bytes: u64,
        /// The device's largest storage binding.
        max_bytes: u64,
    },
    /// The screen is empty or wider or taller than [`MAX_SCREEN_EDGE`](render_model::quad_raster::MAX_SCREEN_EDGE).
    BadScreen {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
    /// The visibility buffer holds fewer than `width * height` 64-bit words.
    VisibilityTooSmall {
        /// Its bytes.
        bytes: u64,
        /// Bytes `width * height` words take.
        needed: u64,
    },
    /// An input buffer cannot be bound as the rasteriser needs it.
    BufferUnusable {
        /// Which input.
        buffer: &'static str,
        /// What it needs (usage, size).
        needs: &'static str,
    },
    /// A page holds more command slots than one indirect dispatch addresses (65535^2).
    TooManyCommands {
        /// The cull output's `commands_per_page`.
        commands_per_page: u32,
    },
    /// The device refused one of the rasteriser's buffers.
    Alloc(AllocError),
}

impl fmt::Display for QuadRasterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            QuadRasterError::MissingInt64Atomics => write!(
                f,
                "the compute quad rasteriser needs SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX, \
                 which the device was created without"
            ),
            QuadRasterError::BadCapacity {
                list,
                bytes,
                max_bytes,
            } => write!(
                f,
                "the {list} list would take {bytes} bytes; it must hold at least one entry and \
                 fit the device's storage binding limit of {max_bytes} bytes"
            ),
            QuadRasterError::BadScreen { width, height } => write!(
                f,
                "a {width}x{height} screen cannot be rasterised: each side must be 1..={}",
                render_model::quad_raster::MAX_SCREEN_EDGE
            ),
            QuadRasterError::VisibilityTooSmall { bytes, needed } => write!(
                f,
                "the visibility buffer has {bytes} bytes; the screen needs {needed}"
            ),
            QuadRasterError::BufferUnusable { buffer, needs } => {
                write!(f, "the {buffer} buffer cannot be bound: it needs {needs}")
            }
            QuadRasterError::TooManyCommands { commands_per_page } => write!(
                f,
                "{commands_per_page} command slots per page exceed one indirect dispatch \
                 (65535 x 65535 workgroups)"
            ),
            QuadRasterError::Alloc(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for QuadRasterError {}

impl From<AllocError> for QuadRasterError {
    fn from(e: AllocError) -> Self {
        QuadRasterError::Alloc(e)
    }
}
