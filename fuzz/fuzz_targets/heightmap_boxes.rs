//! Fuzz target `heightmap_boxes`: runs `mesher_bodies::heightmap_boxes` (see `fuzz/mesher_bodies/` for the properties it checks).
#![no_main]

#[path = "../mesher_bodies/mod.rs"]
mod mesher_bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| mesher_bodies::heightmap_boxes(data));
