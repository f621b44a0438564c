//! Fuzz target `gltf_props`: runs `gltf_props_body::gltf_props` (see `fuzz/gltf_props_body.rs` for the properties it checks).
#![no_main]

#[path = "../gltf_props_body.rs"]
mod gltf_props_body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| gltf_props_body::gltf_props(data));
