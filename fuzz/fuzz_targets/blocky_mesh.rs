//! Fuzz target `blocky_mesh`: runs `bodies::blocky_mesh` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::blocky_mesh(data));
