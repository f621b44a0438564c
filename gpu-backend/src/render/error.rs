//! Why the renderer refused something.

use std::fmt;

use voxel_core::FormatError;

use crate::chunk_table::TableError;
use crate::gigabuffer::{ChunkHandle, GigabufferError};
use crate::readback::ReadbackError;
use crate::timing::TimerError;
use render_model::cull::{CullError, SkirtTooLarge, lod::BadLodSetting};

use super::quad_raster::QuadRasterError;

/// An error of the [`Renderer`](super::Renderer): each names the problem, none is a panic.
#[derive(Debug)]
#[non_exhaustive]
pub enum RenderError {
    /// The output size is zero or larger than the device's texture limit.
    BadSize {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
        /// The device's largest 2D texture edge.
        max: u32,
    },
    /// The device lacks a feature the renderer needs.
    MissingFeature(&'static str),
    /// [`Renderer::set_opaque_path`](crate::render::Renderer::set_opaque_path) asked for a
    /// path this renderer cannot draw with (why).
    OpaquePathUnavailable(&'static str),
    /// The gigabuffer refused an upload or free.
    Gigabuffer(GigabufferError),
    /// The chunk table is full or the slot is stale.
    Table(TableError),
    /// The cull pass could not be set up.
    Cull(CullError),
    /// A chunk record does not encode (non-finite bounds, range overflow).
    Format(FormatError),
    /// A handle that names no resident chunk of this renderer.
    UnknownChunk(ChunkHandle),
    /// Reading the image back failed.
    Readback(ReadbackError),
    /// Collecting the per-pass times failed.
    Timer(TimerError),
    /// A chunk's level of detail is above 15 (`MeshedChunkInfo::MAX_LOD`).
    BadLevel(u32),
    /// A chunk's far-draw data does not fit the renderer (what is wrong, in words).
    BadFarData(String),
    /// A chunk has more skirt elements on one side than a node records.
    Skirt(SkirtTooLarge),
    /// A level-of-detail setting is not a finite non-negative number.
    Lod(BadLodSetting),
    /// The far-draw path asked for cannot run on this device or configuration (why, in
    /// words).
    FarDrawsUnavailable(String),
    /// The depth pyramid of occlusion culling could not be built.
    Hiz(crate::hiz::HizError),
    /// The compute quad rasteriser refused its device, configuration or inputs.
    QuadRaster(QuadRasterError),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::BadSize { width, height, max } => write!(
                f,
                "output size {width}x{height} is invalid: each side must be 1..={max}"
            ),
            RenderError::MissingFeature(feature) => {
                write!(f, "the device lacks {feature}, which the renderer needs")
            }
            RenderError::OpaquePathUnavailable(why) => {
                write!(f, "that opaque path is not available: {why}")
            }
            RenderError::Gigabuffer(e) => write!(f, "gigabuffer: {e}"),
            RenderError::Table(e) => write!(f, "chunk table: {e}"),
            RenderError::Cull(e) => write!(f, "cull pass: {e}"),
            RenderError::Format(e) => write!(f, "chunk record: {e}"),
            RenderError::UnknownChunk(h) => {
                write!(f, "chunk handle {h:?} names no resident chunk")
            }
            RenderError::Readback(e) => write!(f, "{e}"),
            RenderError::Timer(e) => write!(f, "pass timing: {e}"),
            RenderError::BadLevel(level) => {
                write!(f, "chunk level of detail {level} is above the largest, 15")
            }
            RenderError::BadFarData(why) => write!(f, "far-draw data: {why}"),
            RenderError::Skirt(e) => write!(f, "skirts: {e}"),
            RenderError::Lod(e) => write!(f, "{e}"),
            RenderError::FarDrawsUnavailable(why) => write!(f, "far draws unavailable: {why}"),
            RenderError::Hiz(e) => write!(f, "depth pyramid: {e}"),
            RenderError::QuadRaster(e) => write!(f, "quad rasteriser: {e}"),
        }
    }
}

impl std::error::Error for RenderError {}

macro_rules! from_error {
    ($source:ty, $variant:ident) => {
        impl From<$source> for RenderError {
            fn from(e: $source) -> Self {
                RenderError::$variant(e)
            }
        }
    };
}

from_error!(GigabufferError, Gigabuffer);
from_error!(TableError, Table);
from_error!(CullError, Cull);
from_error!(FormatError, Format);
from_error!(ReadbackError, Readback);
from_error!(TimerError, Timer);
from_error!(SkirtTooLarge, Skirt);
from_error!(BadLodSetting, Lod);
from_error!(QuadRasterError, QuadRaster);
