//! Fuzz target `compact_quad`: runs `bodies::compact_quad` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::compact_quad(data));
