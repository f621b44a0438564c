//! Fuzz target `block_vertex`: runs `bodies::block_vertex` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::block_vertex(data));
