//! Fuzz target `region`: runs `region_body::region` (see `fuzz/region_body.rs` for the properties it checks).
#![no_main]

#[path = "../region_body.rs"]
mod region_body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| region_body::region(data));
