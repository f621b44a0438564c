//! The format parity test's parts: inputs (random and edge values per format), the expected
//! words from voxel-core's CPU decoders, the GPU harness, and the comparison.

pub mod compare;
pub mod expected;
pub mod harness;
pub mod inputs;
