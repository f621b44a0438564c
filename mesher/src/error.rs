//! The one error type of the meshers.

use core::fmt;

use voxel_core::BlockId;
use voxel_core::formats::FormatError;

use crate::InstructionSet;

/// Why a mesher could not mesh its input. Meshers check their input and report the first
/// problem; they never panic and never emit a partial mesh as if it were whole.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeshError {
    /// A voxel holds an id the material palette does not know.
    UnknownBlock {
        /// The id.
        id: BlockId,
        /// Its padded position.
        position: [u32; 3],
    },
    /// A density sample is NaN or infinite.
    NonFiniteDensity {
        /// Linear index of the sample in the density grid.
        index: usize,
        /// The value found.
        value: f32,
    },
    /// The input's dimensions do not fit what the mesher supports.
    BadShape {
        /// What is wrong, in words.
        reason: &'static str,
        /// The rejected dimension or length.
        value: usize,
    },
    /// A value did not fit its packed format.
    Format(FormatError),
    /// A mesher was asked to run on an instruction set this CPU lacks.
    UnsupportedInstructionSet(InstructionSet),
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::UnknownBlock { id, position } => {
                write!(
                    f,
                    "voxel at padded {position:?} has block id {} with no material",
                    id.0
                )
            }
            MeshError::NonFiniteDensity { index, value } => {
                write!(f, "density sample {index} is {value}, not a finite number")
            }
            MeshError::BadShape { reason, value } => write!(f, "{reason} (got {value})"),
            MeshError::Format(e) => write!(f, "packing failed: {e}"),
            MeshError::UnsupportedInstructionSet(set) => {
                write!(f, "this CPU cannot run the {set:?} instruction set")
            }
        }
    }
}

impl From<FormatError> for MeshError {
    fn from(e: FormatError) -> Self {
        MeshError::Format(e)
    }
}

#[cfg(feature = "std")]
impl std::error::Error for MeshError {}
