//! Why a screen, a depth image or a pyramid's levels do not fit together.

use std::fmt;

/// A screen size, depth image, visibility buffer or set of pyramid levels that the depth
/// pyramid's rules refuse: each names the problem, none is a panic.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ScreenError {
    /// The screen size is zero or larger than the limit.
    BadSize {
        /// Width asked for, pixels.
        width: u32,
        /// Height asked for, pixels.
        height: u32,
        /// The largest edge accepted.
        max: u32,
    },
    /// A CPU depth image whose length is not `width * height`.
    DepthLength {
        /// `width * height`.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// A CPU visibility buffer whose length is not `width * height`.
    VisibilityLength {
        /// `width * height`.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// CPU levels that are not the pyramid of the stated screen: wrong level count.
    LevelCount {
        /// Levels of the screen's pyramid.
        expected: usize,
        /// Levels given.
        found: usize,
    },
    /// CPU levels that are not the pyramid of the stated screen: a level of the wrong length.
    LevelLength {
        /// The level.
        level: usize,
        /// Its `width * height`.
        expected: usize,
        /// Values given.
        found: usize,
    },
}

impl fmt::Display for ScreenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScreenError::BadSize { width, height, max } => write!(
                f,
                "depth pyramid screen {width}x{height} is invalid: each side must be 1..={max}"
            ),
            ScreenError::DepthLength { expected, found } => write!(
                f,
                "depth image has {found} values, the screen needs {expected}"
            ),
            ScreenError::VisibilityLength { expected, found } => write!(
                f,
                "visibility buffer has {found} values, the screen needs {expected}"
            ),
            ScreenError::LevelCount { expected, found } => write!(
                f,
                "{found} pyramid levels given, the screen's pyramid has {expected}"
            ),
            ScreenError::LevelLength {
                level,
                expected,
                found,
            } => write!(
                f,
                "pyramid level {level} has {found} values, it should have {expected}"
            ),
        }
    }
}

impl std::error::Error for ScreenError {}
