//! Packed GPU formats: the contract between the CPU core and the GPU backend.
