//! Fuzz target `smooth_density`: runs `bodies::smooth_density` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::smooth_density(data));
