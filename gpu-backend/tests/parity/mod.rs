//! The format parity test's parts: inputs (random and edge values per format), the expected
//! words from voxel-core's CPU decoders, the GPU harness, and the comparison.

pub(crate) mod compare;
pub(crate) mod expected;
pub(crate) mod harness;
pub(crate) mod inputs;
