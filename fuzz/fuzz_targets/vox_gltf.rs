//! Fuzz target `vox_gltf`: runs `vox_gltf_body::vox_gltf` (see `fuzz/vox_gltf_body.rs` for the properties it checks).
#![no_main]

#[path = "../vox_gltf_body.rs"]
mod vox_gltf_body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| vox_gltf_body::vox_gltf(data));
