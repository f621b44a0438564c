//! The chunk codec: round trips at every width and size, arbitrary and mutated input never
//! panics, and each malformation gets its named error.

mod storage_support;

use proptest::prelude::*;
use storage_support::{Rng, check_consistent, script, smallest_bits};
use voxel_core::storage::{
    CodecError, DenseChunk, HEADER_LEN, PaletteChunk, VoxelStorage, decode_chunk, encode_chunk,
    encoded_len,
};
use voxel_core::{BlockId, ChunkSize, LocalPos};

fn size() -> impl Strategy<Value = ChunkSize> {
    prop::sample::select(ChunkSize::ALL.to_vec())
}

fn encode(chunk: &PaletteChunk) -> Vec<u8> {
    let mut out = Vec::new();
    encode_chunk(chunk, &mut out);
    out
}

/// A chunk built by a random edit script (any width, free palette entries included).
fn edited_chunk(size: ChunkSize, pool: u64, seed: u64, n: usize) -> PaletteChunk {
    let mut chunk = PaletteChunk::new(size);
    let mut olds = Vec::new();
    for op in script(seed, size, pool, n) {
        storage_support::apply(&mut chunk, op, &mut olds);
    }
    chunk
}

/// A chunk of `ids` distinct ids at the smallest width.
fn chunk_with_ids(size: ChunkSize, ids: usize, seed: u64) -> PaletteChunk {
    let mut rng = Rng::new(seed);
    let mut n = 0usize;
    let dense = DenseChunk::from_fn(size, |_| {
        // Every id appears at least once, the rest at random.
        n += 1;
        let k = if n <= ids {
            n - 1
        } else {
            rng.below(ids as u64) as usize
        };
        BlockId((k * 37) as u16)
    });
    PaletteChunk::from_dense(&dense)
}

/// A hand-built encoding: header fields, palette, voxel bytes.
fn bytes(edge: u8, bits: u8, palette: &[u16], voxels: &[u8]) -> Vec<u8> {
    let mut out = b"VXCH".to_vec();
    out.extend_from_slice(&[1, edge, bits, 0]);
    out.extend_from_slice(&(palette.len() as u16).to_le_bytes());
    for id in palette {
        out.extend_from_slice(&id.to_le_bytes());
    }
    out.extend_from_slice(voxels);
    out
}

/// Decoding must never panic; whatever decodes must be an internally consistent chunk.
fn decode_checked(input: &[u8]) -> Result<Option<PaletteChunk>, TestCaseError> {
    match decode_chunk(input) {
        Ok(chunk) => {
            check_consistent(&chunk).map_err(TestCaseError::fail)?;
            prop_assert_eq!(decode_chunk(&encode(&chunk)), Ok(chunk.clone()));
            Ok(Some(chunk))
        }
        Err(e) => {
            prop_assert!(!e.to_string().is_empty());
            Ok(None)
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn round_trip_of_edited_chunks(
        size in size(),
        pool in prop_oneof![Just(2u64), Just(4), Just(16), Just(200), Just(1000)],
        seed in any::<u64>(),
        n in 0usize..2000,
    ) {
        let mut chunk = edited_chunk(size, pool, seed, n);
        let encoded = encode(&chunk);
        prop_assert_eq!(encoded.len(), encoded_len(&chunk));
        let decoded = decode_chunk(&encoded).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(&decoded, &chunk);
        prop_assert_eq!(decoded.bits_per_voxel(), chunk.bits_per_voxel());
        check_consistent(&decoded).map_err(TestCaseError::fail)?;
        chunk.compact();
        let compact = encode(&chunk);
        prop_assert!(compact.len() <= encoded.len());
        prop_assert_eq!(decode_chunk(&compact), Ok(chunk));
    }

    #[test]
    fn round_trip_at_every_width(
        size in size(),
        ids in prop_oneof![Just(1usize), Just(2), 3usize..=4, 5usize..=16, 17usize..=256, 257usize..=400],
        seed in any::<u64>(),
    ) {
        let ids = ids.min(size.volume());
        let chunk = chunk_with_ids(size, ids, seed);
        prop_assert_eq!(chunk.bits_per_voxel(), smallest_bits(ids));
        let encoded = encode(&chunk);
        let bits = usize::from(chunk.bits_per_voxel());
        let palette = if bits == 16 { 0 } else { ids };
        prop_assert_eq!(encoded.len(), HEADER_LEN + 2 * palette + size.volume() * bits / 8);
        prop_assert_eq!(decode_chunk(&encoded), Ok(chunk));
    }

    #[test]
    fn arbitrary_bytes_never_panic(input in prop::collection::vec(any::<u8>(), 0..700)) {
        decode_checked(&input)?;
        // The same bytes behind a valid magic and version reach the deeper checks.
        let mut prefixed = b"VXCH\x01".to_vec();
        prefixed.extend_from_slice(&input);
        decode_checked(&prefixed)?;
    }

    /// Headers that pass the header checks, with exactly the declared number of random bytes:
    /// exercises the palette and index checks.
    #[test]
    fn well_sized_random_bodies_never_panic(
        edge in prop::sample::select(vec![8u8, 16]),
        bits in prop::sample::select(vec![0u8, 1, 2, 4, 8, 16]),
        len_seed in any::<u16>(),
        seed in any::<u64>(),
    ) {
        let max = match bits { 0 => 1, 16 => 0, b => 1u16 << b };
        let len = if max == 0 { 0 } else { 1 + len_seed % max };
        let mut rng = Rng::new(seed);
        // Small ids so duplicates happen, sometimes.
        let palette: Vec<u16> = (0..len).map(|_| rng.below(u64::from(len) * 4) as u16).collect();
        let volume = usize::from(edge).pow(3);
        let voxels: Vec<u8> = (0..volume * usize::from(bits) / 8).map(|_| rng.next_u64() as u8).collect();
        let input = bytes(edge, bits, &palette, &voxels);
        if let Some(chunk) = decode_checked(&input)? {
            prop_assert_eq!(chunk.size().edge(), u32::from(edge));
        }
    }

    #[test]
    fn mutated_encodings_never_panic(
        size in prop::sample::select(vec![ChunkSize::S8, ChunkSize::S16]),
        pool in prop_oneof![Just(1u64), Just(2), Just(16), Just(300)],
        seed in any::<u64>(),
        at in any::<prop::sample::Index>(),
        flip in 1u8..=255,
        cut in any::<prop::sample::Index>(),
        extra in prop::collection::vec(any::<u8>(), 1..20),
    ) {
        let chunk = edited_chunk(size, pool, seed, 600);
        let valid = encode(&chunk);
        // Flip one byte.
        let mut flipped = valid.clone();
        flipped[at.index(valid.len())] ^= flip;
        prop_assert_ne!(&flipped, &valid);
        decode_checked(&flipped)?;
        // Truncate.
        let got = cut.index(valid.len());
        let needed = if got < HEADER_LEN { HEADER_LEN } else { valid.len() };
        prop_assert_eq!(decode_chunk(&valid[..got]), Err(CodecError::Truncated { needed, got }));
        // Append.
        let mut longer = valid.clone();
        longer.extend_from_slice(&extra);
        prop_assert_eq!(decode_chunk(&longer), Err(CodecError::TrailingBytes { extra: extra.len() }));
    }
}

/// A valid 8^3 chunk with 3 ids (2 bits per voxel) and its encoding.
fn sample() -> (PaletteChunk, Vec<u8>) {
    let size = ChunkSize::S8;
    let mut chunk = PaletteChunk::new(size);
    chunk
        .set(LocalPos::new(1, 0, 0, size).unwrap(), BlockId(5))
        .unwrap();
    chunk
        .set(LocalPos::new(2, 0, 0, size).unwrap(), BlockId(6))
        .unwrap();
    assert_eq!(chunk.bits_per_voxel(), 2);
    let encoded = encode(&chunk);
    (chunk, encoded)
}

#[test]
fn uniform_chunks_encode_in_12_bytes() {
    for size in ChunkSize::ALL {
        let chunk = PaletteChunk::filled(size, BlockId(0xBEEF));
        let encoded = encode(&chunk);
        let mut expect = b"VXCH".to_vec();
        expect.extend_from_slice(&[1, size.edge() as u8, 0, 0, 1, 0, 0xEF, 0xBE]);
        assert_eq!(encoded, expect);
        assert_eq!(decode_chunk(&encoded), Ok(chunk));
    }
}

#[test]
fn layout_is_little_endian_low_bits_first() {
    let (_, encoded) = sample();
    assert_eq!(&encoded[..HEADER_LEN], b"VXCH\x01\x08\x02\x00\x03\x00");
    assert_eq!(&encoded[HEADER_LEN..HEADER_LEN + 6], &[0, 0, 5, 0, 6, 0]);
    // Voxels 0, 1, 2 hold indices 0, 1, 2: 0b10_01_00 in the first byte.
    assert_eq!(encoded[HEADER_LEN + 6], 0b0010_0100);
    assert!(encoded[HEADER_LEN + 7..].iter().all(|&b| b == 0));
    assert_eq!(encoded.len(), HEADER_LEN + 6 + 512 * 2 / 8);
}

#[test]
fn bad_magic() {
    let (_, mut encoded) = sample();
    encoded[3] = b'X';
    assert_eq!(decode_chunk(&encoded), Err(CodecError::BadMagic));
    assert_eq!(decode_chunk(b"VY"), Err(CodecError::BadMagic));
    assert_eq!(
        decode_chunk(b""),
        Err(CodecError::Truncated { needed: 10, got: 0 })
    );
    assert_eq!(
        decode_chunk(b"VX"),
        Err(CodecError::Truncated { needed: 10, got: 2 })
    );
}

#[test]
fn unsupported_version() {
    let (_, mut encoded) = sample();
    encoded[4] = 2;
    assert_eq!(
        decode_chunk(&encoded),
        Err(CodecError::UnsupportedVersion(2))
    );
    encoded[4] = 0;
    assert_eq!(
        decode_chunk(&encoded),
        Err(CodecError::UnsupportedVersion(0))
    );
}

#[test]
fn bad_chunk_edge() {
    let (_, mut encoded) = sample();
    for edge in [0u8, 1, 7, 9, 64, 255] {
        encoded[5] = edge;
        assert_eq!(decode_chunk(&encoded), Err(CodecError::BadChunkEdge(edge)));
    }
}

#[test]
fn bad_bits_per_voxel() {
    let (_, mut encoded) = sample();
    for bits in [3u8, 5, 7, 12, 32, 255] {
        encoded[6] = bits;
        assert_eq!(
            decode_chunk(&encoded),
            Err(CodecError::BadBitsPerVoxel(bits))
        );
    }
}

#[test]
fn non_zero_reserved() {
    let (_, mut encoded) = sample();
    encoded[7] = 0x80;
    assert_eq!(decode_chunk(&encoded), Err(CodecError::NonZeroReserved));
}

#[test]
fn palette_too_large() {
    let zeros = vec![0u8; 512 / 8];
    assert_eq!(
        decode_chunk(&bytes(8, 1, &[1, 2, 3], &zeros)),
        Err(CodecError::PaletteTooLarge { len: 3, bits: 1 })
    );
    assert_eq!(
        decode_chunk(&bytes(8, 0, &[1, 2], &[])),
        Err(CodecError::PaletteTooLarge { len: 2, bits: 0 })
    );
    assert_eq!(
        decode_chunk(&bytes(8, 16, &[1], &vec![0; 1024])),
        Err(CodecError::PaletteTooLarge { len: 1, bits: 16 })
    );
    let many: Vec<u16> = (0..257).collect();
    assert_eq!(
        decode_chunk(&bytes(8, 8, &many, &vec![0; 512])),
        Err(CodecError::PaletteTooLarge { len: 257, bits: 8 })
    );
}

#[test]
fn empty_palette() {
    assert_eq!(
        decode_chunk(&bytes(8, 0, &[], &[])),
        Err(CodecError::EmptyPalette)
    );
    assert_eq!(
        decode_chunk(&bytes(16, 4, &[], &vec![0; 4096 / 2])),
        Err(CodecError::EmptyPalette)
    );
}

#[test]
fn duplicate_palette_entry() {
    let zeros = vec![0u8; 512 * 2 / 8];
    assert_eq!(
        decode_chunk(&bytes(8, 2, &[7, 3, 7], &zeros)),
        Err(CodecError::DuplicatePaletteEntry(BlockId(7)))
    );
}

#[test]
fn palette_index_out_of_range() {
    let mut voxels = vec![0u8; 512 * 2 / 8];
    // Voxel 5 (bits 10..12: byte 1, bits 2..4) holds index 2 of a 2-entry palette.
    voxels[1] = 0b0000_1000;
    assert_eq!(
        decode_chunk(&bytes(8, 2, &[0, 9], &voxels)),
        Err(CodecError::PaletteIndexOutOfRange {
            index: 2,
            len: 2,
            voxel: 5
        })
    );
    // One entry at 1 bit: any set bit is out of range.
    let mut voxels = vec![0u8; 512 / 8];
    voxels[63] = 0x80;
    assert_eq!(
        decode_chunk(&bytes(8, 1, &[4], &voxels)),
        Err(CodecError::PaletteIndexOutOfRange {
            index: 1,
            len: 1,
            voxel: 511
        })
    );
}

#[test]
fn truncated() {
    let (_, encoded) = sample();
    let n = encoded.len();
    assert_eq!(
        decode_chunk(&encoded[..n - 1]),
        Err(CodecError::Truncated {
            needed: n,
            got: n - 1
        })
    );
    assert_eq!(
        decode_chunk(&encoded[..HEADER_LEN + 1]),
        Err(CodecError::Truncated {
            needed: n,
            got: HEADER_LEN + 1
        })
    );
}

#[test]
fn trailing_bytes() {
    let (_, mut encoded) = sample();
    encoded.extend_from_slice(&[0, 0, 0]);
    assert_eq!(
        decode_chunk(&encoded),
        Err(CodecError::TrailingBytes { extra: 3 })
    );
}

/// `NonZeroPadding` guards bits after the last voxel; every supported volume (8^3, 16^3, 32^3,
/// 62^3) times every width is a whole number of bytes, so no encoding of a supported chunk has
/// padding bits. The check itself is unit-tested in `storage/codec.rs`; this pins the premise.
#[test]
fn non_zero_padding_has_no_padding_to_guard_today() {
    for size in ChunkSize::ALL {
        for bits in [1usize, 2, 4, 8, 16] {
            assert_eq!(size.volume() * bits % 8, 0, "{size:?} at {bits} bits");
        }
    }
    // Setting the top bit of the last voxel byte changes a voxel (or breaks an index); it is
    // never mistaken for padding.
    let (_, mut encoded) = sample();
    *encoded.last_mut().unwrap() |= 0x80;
    match decode_chunk(&encoded) {
        Ok(chunk) => assert_eq!(
            chunk.get(LocalPos::new(7, 7, 7, ChunkSize::S8).unwrap()),
            Ok(BlockId(6))
        ),
        Err(e) => panic!("unexpected {e}"),
    }
}

#[test]
fn decoded_uniform_in_disguise_collapses() {
    // A 1-bit chunk whose voxels all use entry 1 decodes as uniform.
    let decoded = decode_chunk(&bytes(8, 1, &[3, 4], &[0xFF; 64])).unwrap();
    assert_eq!(decoded.uniform(), Some(BlockId(4)));
    assert_eq!(decoded.heap_bytes(), 0);
    // And a raw chunk with one id.
    let mut raw = Vec::new();
    for _ in 0..512 {
        raw.extend_from_slice(&9u16.to_le_bytes());
    }
    assert_eq!(
        decode_chunk(&bytes(8, 16, &[], &raw)).unwrap().uniform(),
        Some(BlockId(9))
    );
}
