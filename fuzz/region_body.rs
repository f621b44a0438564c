//! The body of fuzz target `region`, shared with `tests/tests/fuzz_corpus_replay.rs`.
//!
//! Input: byte 0 picks the chunk size (`% 4`: 8, 16, 32, 62), the rest is a region file,
//! decoded as the region its header names (bytes 8..20; region (0, 0, 0) when shorter).
//! Properties: `decode_region` never panics; what it accepts re-encodes, and the re-encoded
//! file decodes to the same chunks with no faults; every fault names a chunk of the region.

use voxel_core::ChunkSize;
use voxel_world::region::{decode_region, encode_region, region_of};

/// Runs the properties above on `data`.
pub(crate) fn region(data: &[u8]) {
    let Some((&pick, file)) = data.split_first() else {
        return;
    };
    let size = ChunkSize::ALL[usize::from(pick % 4)];
    let expected = if file.len() >= 20 {
        [8, 12, 16]
            .map(|at| i32::from_le_bytes([file[at], file[at + 1], file[at + 2], file[at + 3]]))
    } else {
        [0; 3]
    };
    let Ok(decoded) = decode_region(file, expected, size) else {
        return;
    };
    for fault in &decoded.faults {
        assert_eq!(region_of(fault.coord), expected, "fault outside the region");
    }
    let chunks: Vec<_> = decoded.chunks.iter().map(|(c, k)| (*c, k)).collect();
    for (c, _) in &chunks {
        assert_eq!(region_of(*c), expected, "chunk outside the region");
    }
    let again = decode_region(&encode_region(expected, size, &chunks), expected, size)
        .expect("a re-encoded region decodes");
    assert!(again.faults.is_empty());
    assert_eq!(again.chunks, decoded.chunks);
}
