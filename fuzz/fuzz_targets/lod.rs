//! Fuzz target `lod`: runs `mesher_bodies::lod` (see `fuzz/mesher_bodies/` for the properties it checks).
#![no_main]

#[path = "../mesher_bodies/mod.rs"]
mod mesher_bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| mesher_bodies::lod(data));
