//! Fuzz target `packed_quad`: runs `bodies::packed_quad` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::packed_quad(data));
