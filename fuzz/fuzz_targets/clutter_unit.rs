//! Fuzz target `clutter_unit`: runs `bodies::clutter_unit` (see `fuzz/bodies.rs` for the properties it checks).
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::clutter_unit(data));
