//! Why the renderer refused something.

use std::fmt;

use render_model::cull::CullError;
use render_model::cull::lod::BadLodSetting;

use super::passes::far_splat::SplatError;
use super::passes::hiz::HizError;
use super::passes::quad_raster::QuadRasterError;
use super::passes::targets::TargetsError;
use crate::device::DeviceFault;
use crate::device::alloc::AllocError;
use crate::readback::ReadbackError;
use crate::residency::ResidencyError;
use crate::timing::TimerError;

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
    /// Residency refused an upload or a free (memory, tables, records, handles, far-draw
    /// data).
    Residency(ResidencyError),
    /// The cull pass could not be set up.
    Cull(CullError),
    /// Reading the image back failed.
    Readback(ReadbackError),
    /// Collecting the per-pass times failed.
    Timer(TimerError),
    /// A level-of-detail setting is not a finite non-negative number.
    Lod(BadLodSetting),
    /// The far-draw path asked for cannot run on this device or configuration (why, in
    /// words).
    FarDrawsUnavailable(String),
    /// Clutter cannot be drawn with this configuration (why, in words).
    ClutterUnavailable(String),
    /// Shells cannot be drawn: the configuration has no shell pass, or its shell space is not
    /// one gigabuffer page (the reason says which).
    ShellsUnavailable(String),
    /// The depth pyramid of occlusion culling could not be built.
    Hiz(HizError),
    /// The compute quad rasteriser refused its device, configuration or inputs.
    QuadRaster(QuadRasterError),
    /// The device refused a buffer or texture (out of memory, or past a limit).
    Alloc(AllocError),
    /// The props refused an upload.
    Props(crate::render::props::PropError),
    /// The device is lost, or reported an error outside any error scope: nothing more can be
    /// drawn with it.
    Device(DeviceFault),
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
            RenderError::Residency(e) => write!(f, "{e}"),
            RenderError::Cull(e) => write!(f, "cull pass: {e}"),
            RenderError::Readback(e) => write!(f, "{e}"),
            RenderError::Timer(e) => write!(f, "pass timing: {e}"),
            RenderError::Lod(e) => write!(f, "{e}"),
            RenderError::FarDrawsUnavailable(why) => write!(f, "far draws unavailable: {why}"),
            RenderError::ClutterUnavailable(why) => write!(f, "clutter unavailable: {why}"),
            RenderError::ShellsUnavailable(why) => write!(f, "shells unavailable: {why}"),
            RenderError::Hiz(e) => write!(f, "depth pyramid: {e}"),
            RenderError::QuadRaster(e) => write!(f, "quad rasteriser: {e}"),
            RenderError::Alloc(e) => write!(f, "{e}"),
            RenderError::Props(e) => write!(f, "{e}"),
            RenderError::Device(e) => write!(f, "{e}"),
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

from_error!(ResidencyError, Residency);
from_error!(CullError, Cull);
from_error!(ReadbackError, Readback);
from_error!(TimerError, Timer);
from_error!(BadLodSetting, Lod);
from_error!(QuadRasterError, QuadRaster);
from_error!(HizError, Hiz);
from_error!(AllocError, Alloc);
from_error!(DeviceFault, Device);

impl From<TargetsError> for RenderError {
    fn from(e: TargetsError) -> Self {
        match e {
            TargetsError::BadSize(e) => RenderError::BadSize {
                width: e.width,
                height: e.height,
                max: e.max,
            },
            TargetsError::Alloc(e) => RenderError::Alloc(e),
        }
    }
}

impl From<SplatError> for RenderError {
    fn from(e: SplatError) -> Self {
        match e {
            SplatError::TooLarge(e) => RenderError::FarDrawsUnavailable(e.to_string()),
            SplatError::Alloc(e) => RenderError::Alloc(e),
        }
    }
}
