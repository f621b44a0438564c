//! The inputs the benchmarks run on, one module per kind of data. Each function is
//! deterministic: same arguments, same output, on every machine.
//!
//! Later stages add their inputs here (for example padded neighbourhoods for the meshers are
//! built from [`chunks::terrain_world`] with `gather_neighbourhood`).

pub mod chunks;
pub mod formats;
