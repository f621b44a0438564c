//! Fuzz target `chunk_draw_indirect`: runs `bodies::chunk_draw_indirect` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::chunk_draw_indirect(data));
