//! Fuzz target `meshed_chunk_info`: runs `bodies::meshed_chunk_info` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::meshed_chunk_info(data));
