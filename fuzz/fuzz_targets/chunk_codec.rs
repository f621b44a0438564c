//! Fuzz target `chunk_codec`: runs `bodies::chunk_codec` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::chunk_codec(data));
