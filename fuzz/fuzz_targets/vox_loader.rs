//! Fuzz target `vox_loader`: runs `vox_body::vox_loader` (see `fuzz/vox_body.rs` for the properties it checks).
#![no_main]

#[path = "../vox_body.rs"]
mod vox_body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| vox_body::vox_loader(data));
