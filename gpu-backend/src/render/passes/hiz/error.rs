//! Why a depth pyramid or a build refused its input.

use std::fmt;

use render_model::hiz::ScreenError;

use crate::device::alloc::AllocError;
use crate::readback::ReadbackError;

/// An error of the depth pyramid: each names the problem, none is a panic.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum HizError {
    /// The screen, or a CPU image or level set, does not fit the pyramid's rules.
    Screen(ScreenError),
    /// The depth texture is not `Depth32Float`.
    DepthFormat(wgpu::TextureFormat),
    /// The depth texture is not the pyramid's screen size.
    DepthSize {
        /// The pyramid's screen, pixels.
        expected: (u32, u32),
        /// The texture's size.
        found: (u32, u32),
    },
    /// The depth texture cannot be bound for `textureLoad`: it lacks `TEXTURE_BINDING` usage,
    /// is multisampled, or is not a 2D texture.
    DepthNotSampleable,
    /// The visibility buffer lacks `STORAGE` usage.
    VisibilityNotStorage,
    /// The visibility buffer is smaller than `width * height * 8` bytes.
    VisibilityTooSmall {
        /// Bytes the screen needs.
        needed: u64,
        /// The buffer's size.
        found: u64,
    },
    /// `width * height * 8` bytes exceed the device's storage binding limit.
    VisibilityTooLarge {
        /// Bytes the screen needs.
        needed: u64,
        /// `max_storage_buffer_binding_size`.
        max: u64,
    },
    /// Reading the levels back failed.
    Readback(ReadbackError),
    /// The device refused the pyramid's texture or a buffer.
    Alloc(AllocError),
}

impl fmt::Display for HizError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HizError::Screen(e) => write!(f, "{e}"),
            HizError::DepthFormat(format) => {
                write!(
                    f,
                    "depth texture is {format:?}, the pyramid reads Depth32Float"
                )
            }
            HizError::DepthSize { expected, found } => write!(
                f,
                "depth texture is {}x{}, the pyramid's screen is {}x{}",
                found.0, found.1, expected.0, expected.1
            ),
            HizError::DepthNotSampleable => write!(
                f,
                "depth texture cannot be bound for textureLoad (it needs TEXTURE_BINDING usage, \
                 one sample and two dimensions)"
            ),
            HizError::VisibilityNotStorage => {
                write!(f, "visibility buffer lacks STORAGE usage")
            }
            HizError::VisibilityTooSmall { needed, found } => write!(
                f,
                "visibility buffer holds {found} bytes, the screen needs {needed}"
            ),
            HizError::VisibilityTooLarge { needed, max } => write!(
                f,
                "the screen's visibility buffer needs {needed} bytes, more than the device's \
                 storage binding limit of {max}"
            ),
            HizError::Readback(e) => write!(f, "depth pyramid: {e}"),
            HizError::Alloc(e) => write!(f, "depth pyramid: {e}"),
        }
    }
}

impl std::error::Error for HizError {}

impl From<ScreenError> for HizError {
    fn from(e: ScreenError) -> Self {
        HizError::Screen(e)
    }
}

impl From<AllocError> for HizError {
    fn from(e: AllocError) -> Self {
        HizError::Alloc(e)
    }
}

impl From<ReadbackError> for HizError {
    fn from(e: ReadbackError) -> Self {
        HizError::Readback(e)
    }
}
