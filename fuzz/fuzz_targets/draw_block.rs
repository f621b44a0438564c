//! Fuzz target `draw_block`: runs `bodies::draw_block` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::draw_block(data));
