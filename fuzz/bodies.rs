//! The bodies of the fuzz targets, one `pub fn <target>(data: &[u8])` per target.
//!
//! This one file is compiled twice: by each fuzz target (`fuzz/fuzz_targets/<target>.rs`, as
//! `#[path = "../bodies.rs"] mod bodies;`) and by the corpus replay test
//! (`tests/tests/fuzz_corpus_replay.rs`, as `#[path = "../../fuzz/bodies.rs"] mod bodies;`), so
//! `cargo test` replays every committed corpus input through exactly the code that fuzzing ran.
//!
//! Every body checks properties, not just "does not panic":
//!
//! - `chunk_codec`: `decode_chunk` is compared with an independent reference reader of the
//!   documented layout (accepts exactly the valid encodings, and returns the same voxels, rows,
//!   occupancy masks and counts); every error names something that really is wrong with the
//!   input; and the round trip is checked: `decode(encode(c)) == c` (voxel equality), and
//!   `encode(decode(bytes)) == bytes` except for an indexed or raw encoding whose voxels all hold
//!   one id, which the decoder collapses to a uniform chunk and which re-encodes as the 12-byte
//!   uniform form (the one non-canonical case of the format).
//! - the packed formats: the first `size_of::<Format>()` bytes are the packed value (shorter
//!   input returns at once). `decode` must succeed exactly on the bit patterns the layout tables
//!   call valid, return fields in their documented ranges that match the layout table bit for
//!   bit, and `encode(decode(x)) == x` bit for bit. The one exception is the octahedral normal
//!   code of `BlockVertex` / `ClutterUnit`, which is not a bijection: there the decoded normal
//!   must be unit length and re-encode to a code that decodes to the same vector within
//!   [`NORMAL_TOLERANCE`] per component.
//! - `compact_quad` (6 bytes, `[u16; 3]`, no struct): decodes exactly when both deltas are in
//!   `1..=` their base index, to the corners the layout table gives; re-encoding those corners
//!   decodes to them again. Optional bytes `6..22` are 4 `u32` corners to encode: encoded
//!   exactly when they fit by the definition (all `<= 65535`, and the neighbouring pairs
//!   (0, 1), (2, 3) or (1, 2), (3, 0) each differ by `1..=63`), then decoded back unchanged.
//! - `block_vertex` and `clutter_unit` read optional trailing bytes (see each body) for the
//!   quantization extent, a value to check the stated unorm error bound on, an `oct32` code, and
//!   directions to check the stated octahedral error bounds on.
//! - `blocky_mesh` and `smooth_density`: the meshers on arbitrary chunks, palettes and density
//!   grids, against brute-force references of the documented rules (see each body).
#![allow(dead_code)] // Each fuzz target uses one body; the replay test uses them all.

use std::mem::size_of;

use glam::Vec3;
use voxel_core::formats::compact_quad::COMPACT_QUAD_FORMS;
use voxel_core::formats::quantize::{
    UNORM8_MAX, UNORM16_MAX, unorm8_decode, unorm8_encode, unorm16_decode, unorm16_encode,
};
use voxel_core::formats::{
    BlockVertex, COMPACT_QUAD_MAX_DELTA, ChunkDrawIndirect, ChunkDrawInfo, ChunkKind, ClutterUnit,
    DrawBlock, DrawBlockFlags, FaceDirection, FormatError, MeshedChunkInfo,
    OCT16_MAX_ERROR_DEGREES, OCT32_MAX_ERROR_DEGREES, PackedQuad, ShellRun, UnormExtent,
    compact_quad_decode, compact_quad_encode, oct16_decode, oct16_encode, oct32_decode,
    oct32_encode,
};
use voxel_core::storage::{
    CODEC_VERSION, CodecError, DenseChunk, HEADER_LEN, MAGIC, VoxelStorage, decode_chunk,
    encode_chunk, encoded_len,
};
use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, PaddedChunk};

use mesher::blocky::{BlockyMesh, GreedyMesher};
use mesher::smooth::{GridShape, I8_DENSITY_STEP, NoCubes, SmoothMesh, SmoothMeshF32, SurfaceNets};
use mesher::{BlockClasses, InstructionSet, MeshError};

// The blocky meshers' brute-force reference, shared with their tests (path relative to this file).
#[path = "../mesher/tests/blocky_support/reference.rs"]
mod blocky_reference;
use blocky_reference::{covered, reference_faces, voxel};

/// How far (per component, absolute) a decoded octahedral normal may move when it is re-encoded
/// and decoded again: 4 ulps at 1.0. Absolute rather than relative because a component that
/// should be zero can decode as `±4e-8` (the unfold `x - t` is not exact in `f32`) and change
/// sign on the second trip. Measured over all 65,536 `oct16` codes: at most 0.71 ulp.
pub(crate) const NORMAL_TOLERANCE: f32 = 4.0 * f32::EPSILON;

/// How far from 1 the length of a decoded octahedral normal may be ("a few ulps").
pub(crate) const UNIT_LENGTH_TOLERANCE: f64 = 4.0 * f32::EPSILON as f64;

/// The extent used for `BlockVertex` / `ClutterUnit` positions when the input does not carry a
/// valid one.
const DEFAULT_EXTENT: UnormExtent = UnormExtent::padded_chunk(ChunkSize::S32);

// ---------------------------------------------------------------------------------------------
// chunk codec
// ---------------------------------------------------------------------------------------------

/// `decode_chunk` on arbitrary bytes (the whole input is one encoded chunk).
pub(crate) fn chunk_codec(data: &[u8]) {
    let reference = reference_decode(data);
    let chunk = match decode_chunk(data) {
        Ok(chunk) => chunk,
        Err(err) => {
            assert!(
                reference.is_none(),
                "decode_chunk rejected a valid encoding with {err:?}"
            );
            check_codec_error(data, err);
            return;
        }
    };
    let Some(r) = reference else {
        panic!("decode_chunk accepted bytes the documented layout calls invalid");
    };
    let size = chunk.size();
    assert_eq!(size, r.size, "chunk size");
    let volume = size.volume();
    let edge = size.edge_usize();

    // The voxels, in linear order with their positions.
    let mut n = 0;
    for (i, (pos, id)) in chunk.iter().enumerate() {
        assert_eq!(pos.index(size), Ok(i), "iter position of voxel {i}");
        assert_eq!(id.0, r.voxels[i], "voxel {i}");
        n += 1;
    }
    assert_eq!(n, volume, "iter length");

    // Rows, occupancy masks (derived from the packed words with SWAR tricks), counts.
    let dense = DenseChunk::from_palette(&chunk);
    assert_voxels(&dense, &r.voxels, "DenseChunk::from_palette");
    let mut row = vec![BlockId::AIR; edge];
    for z in 0..edge as u32 {
        for y in 0..edge as u32 {
            let start = size.column_index(y, z) * edge;
            let expected = &r.voxels[start..start + edge];
            chunk.copy_row(y, z, &mut row).expect("copy_row in range");
            assert!(
                row.iter().map(|b| b.0).eq(expected.iter().copied()),
                "copy_row({y}, {z})"
            );
            let mask = expected
                .iter()
                .enumerate()
                .filter(|&(_, &id)| id != 0)
                .fold(0u64, |m, (x, _)| m | 1 << x);
            assert_eq!(chunk.column_mask(y, z), Ok(mask), "column_mask({y}, {z})");
            assert_eq!(
                dense.columns()[size.column_index(y, z)],
                mask,
                "DenseChunk mask ({y}, {z})"
            );
        }
    }
    let non_air = r.voxels.iter().filter(|&&id| id != 0).count();
    assert_eq!(chunk.non_air_count(), non_air, "non_air_count");
    let distinct = distinct_ids(&r.voxels);
    assert_eq!(chunk.distinct_ids(), distinct, "distinct_ids");

    // Shape: the decoder keeps the width and palette it was given, except that a chunk whose
    // voxels all hold one id becomes uniform.
    let all_one_id = distinct == 1;
    assert_eq!(
        chunk.uniform().is_some(),
        all_one_id,
        "uniform iff one id covers the chunk"
    );
    if !all_one_id {
        assert_eq!(chunk.bits_per_voxel(), r.bits, "bits_per_voxel");
        assert!(
            chunk
                .palette()
                .iter()
                .map(|b| b.0)
                .eq(r.palette.iter().copied()),
            "palette"
        );
    }

    // Round trip.
    let mut out = Vec::new();
    encode_chunk(&chunk, &mut out);
    assert_eq!(out.len(), encoded_len(&chunk), "encoded_len");
    if all_one_id && r.bits != 0 {
        assert_eq!(
            out,
            uniform_encoding(size, r.voxels[0]),
            "an indexed or raw chunk of one id re-encodes as uniform"
        );
    } else {
        assert_eq!(out, data, "encode(decode(bytes)) == bytes");
    }
    let again = decode_chunk(&out).expect("decode(encode(chunk)) fails");
    assert_eq!(again, chunk, "decode(encode(chunk)) == chunk");
    let mut out2 = Vec::new();
    encode_chunk(&again, &mut out2);
    assert_eq!(out2, out, "a second round trip changes the bytes");

    // `compact` keeps the voxels and reaches the smallest width; its encoding round-trips too.
    // (Voxels compared through `DenseChunk` rather than `==`: the same check, at a fraction of
    // the cost under coverage instrumentation.)
    let mut compact = chunk.clone();
    compact.compact();
    assert_voxels(&DenseChunk::from_palette(&compact), &r.voxels, "compact");
    assert_eq!(
        compact.bits_per_voxel(),
        smallest_width(distinct),
        "compact width"
    );
    let mut small = Vec::new();
    encode_chunk(&compact, &mut small);
    assert!(small.len() <= out.len(), "compact encoding is larger");
    let small_again = decode_chunk(&small).expect("decode(encode(compact chunk)) fails");
    assert_voxels(
        &DenseChunk::from_palette(&small_again),
        &r.voxels,
        "compact round trip",
    );
}

/// `dense` holds exactly `voxels`.
fn assert_voxels(dense: &DenseChunk, voxels: &[u16], what: &str) {
    let ids: &[u16] = bytemuck::cast_slice(dense.as_slice());
    assert!(ids == voxels, "{what}: voxels differ");
}

/// What the documented layout (the table in `storage/codec.rs`) says a valid encoding holds,
/// read without the crate's decoder.
struct RefChunk {
    size: ChunkSize,
    bits: u8,
    palette: Vec<u16>,
    /// The block id of every voxel, linear order.
    voxels: Vec<u16>,
}

/// The header fields, each read as is (no validity checks), if the input has a header.
struct RawHeader {
    version: u8,
    edge: u8,
    bits: u8,
    reserved: u8,
    len: usize,
}

fn raw_header(bytes: &[u8]) -> Option<RawHeader> {
    let h = bytes.get(..HEADER_LEN)?;
    Some(RawHeader {
        version: h[4],
        edge: h[5],
        bits: h[6],
        reserved: h[7],
        len: u16::from_le_bytes([h[8], h[9]]).into(),
    })
}

/// `Some(size)` for the four edges the layout allows.
fn ref_size(edge: u8) -> Option<ChunkSize> {
    let size = match edge {
        8 => ChunkSize::S8,
        16 => ChunkSize::S16,
        32 => ChunkSize::S32,
        62 => ChunkSize::S62,
        _ => return None,
    };
    assert_eq!(size.edge(), u32::from(edge));
    Some(size)
}

/// The largest palette length the layout allows for a width, `None` for an invalid width.
fn ref_max_len(bits: u8) -> Option<usize> {
    match bits {
        0 => Some(1),
        1 | 2 | 4 | 8 => Some(1 << bits),
        16 => Some(0),
        _ => None,
    }
}

/// Bytes holding `volume` voxels of `bits` bits.
fn ref_voxel_bytes(volume: usize, bits: u8) -> usize {
    (volume * usize::from(bits)).div_ceil(8)
}

/// Field `i` of `bits` bits (1, 2, 4, 8 or 16) of the voxel bytes, little-endian bit order.
fn ref_field(data: &[u8], i: usize, bits: u8) -> u32 {
    let bit = i * usize::from(bits);
    if bits == 16 {
        u32::from(u16::from_le_bytes([data[bit / 8], data[bit / 8 + 1]]))
    } else {
        u32::from(data[bit / 8] >> (bit % 8)) & ((1 << bits) - 1)
    }
}

/// The chunk the bytes encode, or `None` when any rule of the layout is broken.
fn reference_decode(bytes: &[u8]) -> Option<RefChunk> {
    if bytes.get(..4)? != MAGIC {
        return None;
    }
    let h = raw_header(bytes)?;
    if h.version != 1 || h.reserved != 0 {
        return None;
    }
    let size = ref_size(h.edge)?;
    let max_len = ref_max_len(h.bits)?;
    let len_ok = match h.bits {
        16 => h.len == 0,
        _ => (1..=max_len).contains(&h.len),
    };
    if !len_ok {
        return None;
    }
    let volume = size.volume();
    if bytes.len() != HEADER_LEN + 2 * h.len + ref_voxel_bytes(volume, h.bits) {
        return None;
    }
    let palette: Vec<u16> = bytes[HEADER_LEN..HEADER_LEN + 2 * h.len]
        .chunks_exact(2)
        .map(|b| u16::from_le_bytes([b[0], b[1]]))
        .collect();
    let mut sorted = palette.clone();
    sorted.sort_unstable();
    sorted.dedup();
    if sorted.len() != palette.len() {
        return None;
    }
    let data = &bytes[HEADER_LEN + 2 * h.len..];
    let used = volume * usize::from(h.bits) % 8;
    if used != 0 && data.last().is_some_and(|&b| b >> used != 0) {
        return None;
    }
    let voxels = match h.bits {
        0 => vec![palette[0]; volume],
        16 => (0..volume).map(|i| ref_field(data, i, 16) as u16).collect(),
        bits => (0..volume)
            .map(|i| palette.get(ref_field(data, i, bits) as usize).copied())
            .collect::<Option<Vec<u16>>>()?,
    };
    Some(RefChunk {
        size,
        bits: h.bits,
        palette,
        voxels,
    })
}

/// Checks that `err` names something that really is wrong with `bytes`.
fn check_codec_error(bytes: &[u8], err: CodecError) {
    let h = raw_header(bytes);
    match err {
        CodecError::BadMagic => {
            let n = bytes.len().min(4);
            assert_ne!(bytes[..n], MAGIC[..n], "{err:?}");
        }
        CodecError::UnsupportedVersion(v) => {
            assert_eq!(bytes.get(4), Some(&v), "{err:?}");
            assert_ne!(v, CODEC_VERSION, "{err:?}");
        }
        CodecError::BadChunkEdge(e) => {
            assert_eq!(bytes.get(5), Some(&e), "{err:?}");
            assert!(ref_size(e).is_none(), "{err:?}");
        }
        CodecError::BadBitsPerVoxel(b) => {
            assert_eq!(bytes.get(6), Some(&b), "{err:?}");
            assert!(ref_max_len(b).is_none(), "{err:?}");
        }
        CodecError::NonZeroReserved => {
            assert!(bytes.get(7).is_some_and(|&r| r != 0), "{err:?}");
        }
        CodecError::PaletteTooLarge { len, bits } => {
            let h = h.expect("PaletteTooLarge without a header");
            assert_eq!((h.len, h.bits), (usize::from(len), bits), "{err:?}");
            assert!(h.len > ref_max_len(bits).expect("valid width"), "{err:?}");
        }
        CodecError::EmptyPalette => {
            let h = h.expect("EmptyPalette without a header");
            assert_eq!(h.len, 0, "{err:?}");
            assert_ne!(h.bits, 16, "{err:?}");
        }
        CodecError::DuplicatePaletteEntry(id) => {
            let h = h.expect("DuplicatePaletteEntry without a header");
            let palette = &bytes[HEADER_LEN..HEADER_LEN + 2 * h.len];
            let copies = palette
                .chunks_exact(2)
                .filter(|b| u16::from_le_bytes([b[0], b[1]]) == id.0)
                .count();
            assert!(copies >= 2, "{err:?}");
        }
        CodecError::PaletteIndexOutOfRange { index, len, voxel } => {
            let h = h.expect("PaletteIndexOutOfRange without a header");
            let size = ref_size(h.edge).expect("valid edge");
            assert_eq!(h.len, usize::from(len), "{err:?}");
            assert!(voxel < size.volume(), "{err:?}");
            assert!(index >= u32::from(len), "{err:?}");
            let data = &bytes[HEADER_LEN + 2 * h.len..];
            assert_eq!(ref_field(data, voxel, h.bits), index, "{err:?}");
        }
        CodecError::Truncated { needed, got } => {
            assert_eq!(got, bytes.len(), "{err:?}");
            assert!(needed > got, "{err:?}");
        }
        CodecError::TrailingBytes { extra } => {
            let h = h.expect("TrailingBytes without a header");
            let size = ref_size(h.edge).expect("valid edge");
            let needed = HEADER_LEN + 2 * h.len + ref_voxel_bytes(size.volume(), h.bits);
            assert!(extra > 0, "{err:?}");
            assert_eq!(needed + extra, bytes.len(), "{err:?}");
        }
        CodecError::NonZeroPadding => {
            panic!("{err:?}: no supported chunk volume leaves padding bits");
        }
        // A variant added later must get a check here.
        _ => panic!("{err:?}: an error this check does not know"),
    }
}

/// The 12-byte encoding of a chunk whose every voxel is `id`.
fn uniform_encoding(size: ChunkSize, id: u16) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&[1, size.edge() as u8, 0, 0, 1, 0]);
    out.extend_from_slice(&id.to_le_bytes());
    out
}

/// The number of distinct values in `voxels`.
fn distinct_ids(voxels: &[u16]) -> usize {
    let mut seen = vec![0u64; 1 << 10];
    let mut n = 0;
    for &id in voxels {
        let (word, bit) = (usize::from(id) / 64, id % 64);
        if seen[word] & 1 << bit == 0 {
            seen[word] |= 1 << bit;
            n += 1;
        }
    }
    n
}

/// The width `PaletteChunk::compact` promises for `distinct` ids.
fn smallest_width(distinct: usize) -> u8 {
    match distinct {
        0..=1 => 0,
        2 => 1,
        3..=4 => 2,
        5..=16 => 4,
        17..=256 => 8,
        _ => 16,
    }
}

// ---------------------------------------------------------------------------------------------
// packed formats: helpers
// ---------------------------------------------------------------------------------------------

/// The first `size_of::<T>()` bytes as a `T`, or `None` if the input is shorter.
fn read<T: bytemuck::AnyBitPattern>(data: &[u8]) -> Option<T> {
    data.get(..size_of::<T>()).map(bytemuck::pod_read_unaligned)
}

/// The little-endian `f32` at `at`, if the input reaches that far.
fn f32_at(data: &[u8], at: usize) -> Option<f32> {
    read::<[u8; 4]>(data.get(at..)?).map(f32::from_le_bytes)
}

/// The little-endian `u32` at `at`, if the input reaches that far.
fn u32_at(data: &[u8], at: usize) -> Option<u32> {
    read::<[u8; 4]>(data.get(at..)?).map(u32::from_le_bytes)
}

/// Three little-endian `f32` at `at`, if the input reaches that far.
fn vec3_at(data: &[u8], at: usize) -> Option<Vec3> {
    Some(Vec3::new(
        f32_at(data, at)?,
        f32_at(data, at + 4)?,
        f32_at(data, at + 8)?,
    ))
}

/// The position extent: the `f32` at `at` when it is a valid extent, else [`DEFAULT_EXTENT`].
/// Checks that `UnormExtent::new` accepts exactly the finite, normal, positive values.
fn extent_at(data: &[u8], at: usize) -> UnormExtent {
    let Some(x) = f32_at(data, at) else {
        return DEFAULT_EXTENT;
    };
    let valid = x.is_normal() && x > 0.0;
    match UnormExtent::new(x) {
        Ok(extent) => {
            assert!(valid, "UnormExtent::new accepted {x:e}");
            assert_eq!(extent.get().to_bits(), x.to_bits());
            extent
        }
        Err(err) => {
            assert!(!valid, "UnormExtent::new rejected {x:e}: {err:?}");
            assert!(
                matches!(
                    err,
                    FormatError::InvalidFloat {
                        field: "extent",
                        ..
                    }
                ),
                "{err:?}"
            );
            DEFAULT_EXTENT
        }
    }
}

/// A decoded unorm16 value: in `0..=extent`, exact at both ends.
fn check_unorm16(code: u16, value: f32, extent: UnormExtent, what: &str, axis: usize) {
    assert!(
        (0.0..=extent.get()).contains(&value),
        "{what}[{axis}]: code {code} decodes to {value:e}, outside 0..={:e}",
        extent.get()
    );
    if code == 0 {
        assert_eq!(value, 0.0, "{what}[{axis}]: code 0");
    }
    if code == UNORM16_MAX {
        assert_eq!(
            value,
            extent.get(),
            "{what}[{axis}]: the largest code is the extent"
        );
    }
}

/// A decoded unorm8 value: in `0..=1`, exact at both ends.
fn check_unorm8(code: u8, value: f32, what: &str, axis: usize) {
    assert!((0.0..=1.0).contains(&value), "{what}[{axis}]: {value:e}");
    if code == 0 {
        assert_eq!(value, 0.0, "{what}[{axis}]: code 0");
    }
    if code == UNORM8_MAX {
        assert_eq!(value, 1.0, "{what}[{axis}]: code 255");
    }
}

/// The stated unorm16 bound on an arbitrary value: values in `0..=extent` quantize to within
/// `extent.max_error()`, everything else is rejected.
fn check_unorm16_bound(value: f32, extent: UnormExtent) {
    let in_range = (0.0..=extent.get()).contains(&value);
    match unorm16_encode(value, extent) {
        Ok(code) => {
            assert!(in_range, "unorm16_encode accepted {value:e}");
            let back = unorm16_decode(code, extent);
            let error = (f64::from(back) - f64::from(value)).abs();
            assert!(
                error <= f64::from(extent.max_error()),
                "unorm16 error {error:e} for {value:e} at extent {:e} exceeds {:e}",
                extent.get(),
                extent.max_error()
            );
        }
        Err(err) => {
            assert!(!in_range, "unorm16_encode rejected {value:e}: {err:?}");
            assert!(
                matches!(err, FormatError::QuantizeOutOfRange { .. }),
                "{err:?}"
            );
        }
    }
}

/// The stated unorm8 bound, like [`check_unorm16_bound`] over `0..=1`.
fn check_unorm8_bound(value: f32) {
    let in_range = (0.0..=1.0).contains(&value);
    match unorm8_encode(value) {
        Ok(code) => {
            assert!(in_range, "unorm8_encode accepted {value:e}");
            let error = (f64::from(unorm8_decode(code)) - f64::from(value)).abs();
            let bound = UnormExtent::UNIT.max_error_unorm8();
            assert!(
                error <= f64::from(bound),
                "unorm8 error {error:e} for {value:e} exceeds {bound:e}"
            );
        }
        Err(err) => {
            assert!(!in_range, "unorm8_encode rejected {value:e}: {err:?}");
            assert!(
                matches!(err, FormatError::QuantizeOutOfRange { .. }),
                "{err:?}"
            );
        }
    }
}

/// A decoded octahedral normal has unit length within a few ulps.
fn check_unit(n: Vec3, what: &str) {
    assert!(n.is_finite(), "{what}: {n:?}");
    let [x, y, z] = n.to_array().map(f64::from);
    let len = (x * x + y * y + z * z).sqrt();
    assert!(
        (len - 1.0).abs() <= UNIT_LENGTH_TOLERANCE,
        "{what}: length {len} of {n:?}"
    );
}

/// `decoded` (from some code) re-encoded as `code_again` decodes within [`NORMAL_TOLERANCE`].
fn check_same_normal(decoded: Vec3, again: Vec3, what: &str) {
    let d = (decoded - again).abs().max_element();
    assert!(
        d <= NORMAL_TOLERANCE,
        "{what}: decoded {decoded:?} re-encodes to {again:?} ({d:e} apart)"
    );
}

/// The angle in degrees between two finite non-zero vectors, computed in `f64`.
fn angle_degrees(a: Vec3, b: Vec3) -> f64 {
    let a = a.to_array().map(f64::from);
    let b = b.to_array().map(f64::from);
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let sin = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    sin.atan2(dot).to_degrees()
}

/// An `oct16` code: decodes to a unit vector, and re-encodes to (nearly) the same vector.
fn check_oct16_code(code: u16, what: &str) -> u16 {
    let n = oct16_decode(code);
    check_unit(n, what);
    let again = oct16_encode(n).unwrap_or_else(|e| panic!("{what}: {n:?} does not encode: {e:?}"));
    check_same_normal(n, oct16_decode(again), what);
    again
}

/// An `oct32` code: decodes to a unit vector, and re-encodes to (nearly) the same vector.
fn check_oct32_code(code: u32) {
    let n = oct32_decode(code);
    check_unit(n, "oct32");
    let again = oct32_encode(n).unwrap_or_else(|e| panic!("oct32: {n:?} does not encode: {e:?}"));
    check_same_normal(n, oct32_decode(again), "oct32");
}

/// A direction is encoded iff it is finite and non-zero, then decodes within the stated angle.
fn check_oct_bound(direction: Vec3, bits32: bool) {
    let valid = direction.is_finite() && direction.abs().max_element() > 0.0;
    let (result, decoded, bound) = if bits32 {
        let r = oct32_encode(direction);
        (r.map(|_| ()), r.map(oct32_decode), OCT32_MAX_ERROR_DEGREES)
    } else {
        let r = oct16_encode(direction);
        (r.map(|_| ()), r.map(oct16_decode), OCT16_MAX_ERROR_DEGREES)
    };
    match (result, decoded) {
        (Ok(()), Ok(n)) => {
            assert!(valid, "encoded an invalid direction {direction:?}");
            check_unit(n, "octahedral bound");
            let angle = angle_degrees(direction, n);
            assert!(
                angle <= f64::from(bound),
                "{direction:?} decodes {angle} degrees away (bound {bound}, 32 bits: {bits32})"
            );
        }
        (Err(err), _) | (_, Err(err)) => {
            assert!(!valid, "rejected the direction {direction:?}: {err:?}");
            assert!(matches!(err, FormatError::InvalidNormal { .. }), "{err:?}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// packed formats: bodies
// ---------------------------------------------------------------------------------------------

/// `DrawBlock` (4 bytes): every bit pattern decodes and round-trips.
pub(crate) fn draw_block(data: &[u8]) {
    let Some(packed) = read::<DrawBlock>(data) else {
        return;
    };
    let b = packed.bits;
    let f = packed.decode();
    assert_eq!(u32::from(f.flags.bits()), b & 0xF, "flags");
    assert_eq!(
        f.position,
        [(b >> 4) & 0xF, (b >> 8) & 0xF, (b >> 12) & 0xF],
        "position"
    );
    assert_eq!(u32::from(f.block.0), b >> 16, "block");
    assert!(f.position.iter().all(|&p| p <= DrawBlock::MAX_POSITION));
    assert_eq!(DrawBlockFlags::from_bits(f.flags.bits()), Ok(f.flags));
    for (bit, flag) in [
        DrawBlockFlags::TRANSPARENT,
        DrawBlockFlags::EMISSIVE,
        DrawBlockFlags::SMOOTH,
        DrawBlockFlags::HAS_CLUTTER,
    ]
    .into_iter()
    .enumerate()
    {
        assert_eq!(f.flags.contains(flag), b & 1 << bit != 0, "flag bit {bit}");
    }
    let back = DrawBlock::encode(&f).expect("decoded DrawBlock must encode");
    assert_eq!(back.bits, b, "encode(decode(x)) == x");
}

/// `PackedQuad` (8 bytes): decodes exactly when the reserved bits are clear and the face is
/// `0..6`; then round-trips and its corners span a `width x height` rectangle in the face plane.
/// `ShellRun::decode` on any 8 bytes: it fails exactly on a position axis above 63, a height
/// of 0 or past 64 voxels, a width past 64 voxels, or a side mask of 0 (naming that
/// field), and what it accepts holds the bytes' fields and encodes back to the same bytes.
pub(crate) fn shell_run(data: &[u8]) {
    let Some(run) = read::<ShellRun>(data) else {
        return;
    };
    let [x, z, y, height] = [run.x, run.z, run.y, run.height].map(u32::from);
    match run.decode() {
        Ok(f) => {
            assert_eq!(f.position, [x, y, z]);
            assert_eq!(
                (f.height, f.block.0, f.sides),
                (height, run.block, run.sides & 63)
            );
            assert_eq!(f.width, u32::from(run.wide & 63) + 1);
            assert_eq!(f.feet, run.sides >> 6 | (run.wide >> 6) << 2);
            assert!(x.max(y).max(z) <= 63 && x + f.width <= 64, "{run:?}");
            assert!(
                height >= 1 && y + height <= 64 && (1..64).contains(&(run.sides & 63)),
                "{run:?}"
            );
            assert_eq!(ShellRun::encode(&f), Ok(run), "decoded runs encode back");
        }
        Err(FormatError::IntegerOutOfRange { field, value, .. }) => {
            let bad = match field {
                "ShellRun.x" => x > 63,
                "ShellRun.y" => y > 63,
                "ShellRun.z" => z > 63,
                "ShellRun.height" => height == 0 || y + height > 64,
                "ShellRun.width" => x + u32::from(run.wide & 63) + 1 > 64,
                "ShellRun.sides" => run.sides & 63 == 0,
                other => panic!("unexpected field {other} for {run:?}"),
            };
            assert!(bad && value >= 0, "{field} = {value} named for {run:?}");
        }
        Err(other) => panic!("unexpected ShellRun error {other:?}"),
    }
}

pub(crate) fn packed_quad(data: &[u8]) {
    let Some(packed) = read::<PackedQuad>(data) else {
        return;
    };
    let (w0, w1) = (packed.position_size, packed.face_ao_block);
    let (reserved0, reserved1) = (w0 & !0 << 30, w1 & !0 << 27);
    let face = (w1 & 7) as u8;
    let f = match packed.decode() {
        Ok(f) => f,
        Err(err) => {
            match err {
                FormatError::ReservedBitsSet {
                    field: "PackedQuad.position_size",
                    bits,
                } => assert!(bits != 0 && bits == reserved0, "{err:?}"),
                FormatError::ReservedBitsSet {
                    field: "PackedQuad.face_ao_block",
                    bits,
                } => assert!(bits != 0 && bits == reserved1, "{err:?}"),
                FormatError::InvalidFaceDirection { value } => {
                    assert!(value == face && face >= 6, "{err:?}")
                }
                other => panic!("unexpected PackedQuad error {other:?}"),
            }
            return;
        }
    };
    assert!(
        reserved0 == 0 && reserved1 == 0 && face < 6,
        "decoded {packed:?}, which has reserved bits set or face {face}"
    );
    // The layout table, field by field.
    assert_eq!(f.position, [w0 & 63, (w0 >> 6) & 63, (w0 >> 12) & 63]);
    assert_eq!(f.width, ((w0 >> 18) & 63) + 1, "width");
    assert_eq!(f.height, ((w0 >> 24) & 63) + 1, "height");
    assert_eq!(f.face.index(), face, "face");
    for (i, &ao) in f.ao.iter().enumerate() {
        assert_eq!(u32::from(ao), (w1 >> (3 + 2 * i)) & 3, "ao[{i}]");
        assert!(ao <= PackedQuad::MAX_AO);
    }
    assert_eq!(u32::from(f.block.0), (w1 >> 11) & 0xFFFF, "block");
    assert!(f.position.iter().all(|&p| p <= PackedQuad::MAX_POSITION));
    assert!((1..=PackedQuad::MAX_SIZE).contains(&f.width));
    assert!((1..=PackedQuad::MAX_SIZE).contains(&f.height));
    let back = PackedQuad::encode(&f).expect("decoded PackedQuad must encode");
    assert_eq!(back, packed, "encode(decode(x)) == x");

    // Corners: in the face plane, spanning width x height, at most 127.
    let corners = f.corners();
    let (n, u, v) = (
        f.face.normal_axis(),
        f.face.width_axis(),
        f.face.height_axis(),
    );
    let plane = f.position[n] + u32::from(f.face.is_positive());
    let mut expected_base = f.position;
    expected_base[n] = plane;
    assert_eq!(corners[0], expected_base, "corner 0 is the quad's minimum");
    for c in corners {
        assert!(c.iter().all(|&a| a <= 127), "corner {c:?}");
        assert_eq!(c[n], plane, "corner {c:?} off the face plane");
    }
    let span = |axis: usize| {
        let lo = corners.iter().map(|c| c[axis]).min().unwrap_or(0);
        let hi = corners.iter().map(|c| c[axis]).max().unwrap_or(0);
        hi - lo
    };
    assert_eq!((span(u), span(v)), (f.width, f.height), "corner spans");
    // Counter-clockwise seen from outside: (c1 - c0) x (c2 - c0) points along the normal.
    let d = |a: [u32; 3], b: [u32; 3]| [0, 1, 2].map(|k| i64::from(b[k]) - i64::from(a[k]));
    let (e1, e2) = (d(corners[0], corners[1]), d(corners[0], corners[2]));
    let cross = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let normal = f.face.normal().map(i64::from);
    assert!(
        (0..3).map(|k| cross[k] * normal[k]).sum::<i64>() > 0,
        "corners of {f:?} are not counter-clockwise"
    );
}

/// `BlockVertex` (16 bytes, every bit pattern decodes). Optional trailing bytes:
/// `16..20` the position extent (`f32`; invalid or absent: the padded 32^3 chunk), `20..24` a
/// value to check the unorm16 bound on, `24..36` a direction to check the oct16 bound on.
pub(crate) fn block_vertex(data: &[u8]) {
    let Some(packed) = read::<BlockVertex>(data) else {
        return;
    };
    let extent = extent_at(data, 16);
    let f = packed.decode(extent);
    for (axis, (code, value)) in packed
        .position
        .into_iter()
        .zip(f.position.to_array())
        .enumerate()
    {
        check_unorm16(code, value, extent, "BlockVertex.position", axis);
    }
    for (axis, (code, value)) in packed.uv.into_iter().zip(f.uv.to_array()).enumerate() {
        check_unorm16(code, value, UnormExtent::UNIT, "BlockVertex.uv", axis);
    }
    assert_eq!((f.block.0, f.extra), (packed.block, packed.extra));
    let normal_again = check_oct16_code(packed.normal, "BlockVertex.normal");

    let back = BlockVertex::encode(&f, extent).expect("decoded BlockVertex must encode");
    assert_eq!(back.position, packed.position, "position round trip");
    assert_eq!(back.uv, packed.uv, "uv round trip");
    assert_eq!((back.block, back.extra), (packed.block, packed.extra));
    assert_eq!(
        back.normal, normal_again,
        "normal re-encodes like oct16_encode"
    );

    if let Some(value) = f32_at(data, 20) {
        check_unorm16_bound(value, extent);
    }
    if let Some(direction) = vec3_at(data, 24) {
        check_oct_bound(direction, false);
    }
}

/// `ClutterUnit` (20 bytes, every bit pattern decodes). Optional trailing bytes:
/// `20..24` the position extent (`f32`; invalid or absent: the padded 32^3 chunk), `24..28` a
/// value to check the unorm8 bound on, `28..32` an `oct32` code (no packed format stores one),
/// `32..44` a direction to check the oct32 bound on.
pub(crate) fn clutter_unit(data: &[u8]) {
    let Some(packed) = read::<ClutterUnit>(data) else {
        return;
    };
    let extent = extent_at(data, 20);
    let f = packed.decode(extent);
    for (axis, (code, value)) in packed
        .position
        .into_iter()
        .zip(f.position.to_array())
        .enumerate()
    {
        check_unorm16(code, value, extent, "ClutterUnit.position", axis);
    }
    for (axis, (code, value)) in packed.uv.into_iter().zip(f.uv.to_array()).enumerate() {
        check_unorm16(code, value, UnormExtent::UNIT, "ClutterUnit.uv", axis);
    }
    for (axis, (code, value)) in packed
        .uv_size
        .into_iter()
        .zip(f.uv_size.to_array())
        .enumerate()
    {
        check_unorm8(code, value, "ClutterUnit.uv_size", axis);
    }
    let s = packed.settings;
    assert_eq!(u16::from(f.kind), s & 0xFF, "kind");
    assert_eq!(u16::from(f.scale_step), (s >> 8) & 0xF, "scale_step");
    assert_eq!(u16::from(f.seed), s >> 12, "seed");
    assert!(f.scale_step <= ClutterUnit::MAX_SCALE_STEP && f.seed <= ClutterUnit::MAX_SEED);
    assert_eq!(f.tint, packed.tint.to_le_bytes(), "tint");
    let normal_again = check_oct16_code(packed.normal, "ClutterUnit.normal");

    let back = ClutterUnit::encode(&f, extent).expect("decoded ClutterUnit must encode");
    assert_eq!(back.position, packed.position, "position round trip");
    assert_eq!(back.settings, packed.settings, "settings round trip");
    assert_eq!(back.uv, packed.uv, "uv round trip");
    assert_eq!(back.uv_size, packed.uv_size, "uv_size round trip");
    assert_eq!(back.tint, packed.tint, "tint round trip");
    assert_eq!(
        back.normal, normal_again,
        "normal re-encodes like oct16_encode"
    );

    if let Some(value) = f32_at(data, 24) {
        check_unorm8_bound(value);
    }
    if let Some(code) = u32_at(data, 28) {
        check_oct32_code(code);
    }
    if let Some(direction) = vec3_at(data, 32) {
        check_oct_bound(direction, true);
    }
}

/// `ChunkDrawInfo` (24 bytes): decodes exactly when the kind is 0..=2 and both sentinels are
/// `>= -1`; then round-trips.
pub(crate) fn chunk_draw_info(data: &[u8]) {
    let Some(packed) = read::<ChunkDrawInfo>(data) else {
        return;
    };
    let valid = packed.kind <= 2 && packed.draw_count >= -1 && packed.gigabuffer_index >= -1;
    let f = match packed.decode() {
        Ok(f) => f,
        Err(err) => {
            assert!(!valid, "rejected {packed:?}: {err:?}");
            match err {
                FormatError::InvalidChunkKind { value } => {
                    assert!(value == packed.kind && value > 2, "{err:?}")
                }
                FormatError::IntegerOutOfRange {
                    field,
                    value,
                    min: -1,
                    max,
                } if max == i64::from(i32::MAX) => {
                    let stored = match field {
                        "ChunkDrawInfo.draw_count" => packed.draw_count,
                        "ChunkDrawInfo.gigabuffer_index" => packed.gigabuffer_index,
                        other => panic!("unexpected field {other}"),
                    };
                    assert!(value == i64::from(stored) && value < -1, "{err:?}");
                }
                other => panic!("unexpected ChunkDrawInfo error {other:?}"),
            }
            return;
        }
    };
    assert!(valid, "decoded the invalid {packed:?}");
    assert_eq!([f.chunk.x, f.chunk.y, f.chunk.z], packed.chunk, "chunk");
    assert_eq!(f.kind as u32, packed.kind, "kind");
    assert!(ChunkKind::ALL.contains(&f.kind));
    let sentinel = |v: Option<u32>| v.map_or(-1, i64::from);
    assert_eq!(sentinel(f.draw_count), i64::from(packed.draw_count));
    assert_eq!(
        sentinel(f.gigabuffer_index),
        i64::from(packed.gigabuffer_index)
    );
    let back = ChunkDrawInfo::encode(&f).expect("decoded ChunkDrawInfo must encode");
    assert_eq!(back, packed, "encode(decode(x)) == x");
}

/// `MeshedChunkInfo` (112 bytes): decodes exactly when lod <= 15, the centre is finite, the
/// extent finite and `>= 0`, and every range ends within `u32`; then round-trips bit for bit
/// and every per-face range is contiguous and in bounds.
pub(crate) fn meshed_chunk_info(data: &[u8]) {
    let Some(packed) = read::<MeshedChunkInfo>(data) else {
        return;
    };
    let fits = |end: u64| end <= u64::from(u32::MAX);
    let valid = packed.lod <= MeshedChunkInfo::MAX_LOD
        && packed.centre.iter().all(|c| c.is_finite())
        && packed.extent.iter().all(|e| e.is_finite() && *e >= 0.0)
        && fits(u64::from(packed.opaque_quads.offset) + packed.opaque_quads.total())
        && fits(u64::from(packed.transparent_quads.offset) + packed.transparent_quads.total())
        && fits(packed.smooth_vertices.end())
        && fits(packed.clutter_units.end());
    let f = match packed.decode() {
        Ok(f) => f,
        Err(err) => {
            assert!(!valid, "rejected a valid MeshedChunkInfo: {err:?}");
            let field = match err {
                FormatError::IntegerOutOfRange { field, .. }
                | FormatError::InvalidFloat { field, .. }
                | FormatError::RangeOverflow { field, .. } => field,
                other => panic!("unexpected MeshedChunkInfo error {other:?}"),
            };
            assert!(field.starts_with("MeshedChunkInfo."), "{err:?}");
            return;
        }
    };
    assert!(valid, "decoded an invalid MeshedChunkInfo: {packed:?}");
    assert_eq!([f.chunk.x, f.chunk.y, f.chunk.z], packed.chunk, "chunk");
    assert!(f.lod <= MeshedChunkInfo::MAX_LOD);
    for range in [f.opaque_quads, f.transparent_quads] {
        let mut next = u64::from(range.offset);
        for face in FaceDirection::ALL {
            let r = range
                .face_range(face)
                .unwrap_or_else(|| panic!("{face:?} range of a valid {range:?}"));
            assert_eq!(
                u64::from(r.offset),
                next,
                "{face:?} range is not contiguous"
            );
            assert_eq!(r.count, range.counts[usize::from(face.index())]);
            next = r.end();
        }
        assert_eq!(next, u64::from(range.offset) + range.total());
    }
    let back = MeshedChunkInfo::encode(&f).expect("decoded MeshedChunkInfo must encode");
    assert_eq!(
        bytemuck::bytes_of(&back),
        bytemuck::bytes_of(&packed),
        "encode(decode(x)) == x bit for bit"
    );
}

/// `ChunkDrawIndirect` (32 bytes): every bit pattern decodes and round-trips.
pub(crate) fn chunk_draw_indirect(data: &[u8]) {
    let Some(packed) = read::<ChunkDrawIndirect>(data) else {
        return;
    };
    let f = packed.decode();
    assert_eq!(
        (
            f.index_count,
            f.instance_count,
            f.first_index,
            f.base_vertex,
            f.first_instance
        ),
        (
            packed.index_count,
            packed.instance_count,
            packed.first_index,
            packed.base_vertex,
            packed.first_instance
        )
    );
    assert_eq!([f.chunk.x, f.chunk.y, f.chunk.z], packed.chunk, "chunk");
    assert_eq!(
        ChunkDrawIndirect::encode(&f),
        packed,
        "encode(decode(x)) == x"
    );
}

/// Compact quad (6 bytes, three little-endian `u16`): decodes exactly when `1 <= da <= a` and
/// `1 <= db <= b`, to the corners of the layout table (form and rotation), and those corners
/// re-encode to a record that decodes to them; bytes `6..22`, when present, are 4 little-endian
/// `u32` corners that encode exactly when they fit and then decode back unchanged.
pub(crate) fn compact_quad(data: &[u8]) {
    let Some(bytes) = read::<[u8; 6]>(data) else {
        return;
    };
    let record = [0, 2, 4].map(|i| u16::from_le_bytes([bytes[i], bytes[i + 1]]));
    let [a, b, info] = record.map(u32::from);
    let (da, db) = (info & 63, (info >> 6) & 63);
    let (form, rotation) = ((info >> 12) & 3, info >> 14);
    match compact_quad_decode(record) {
        Ok(corners) => {
            assert!((1..=a).contains(&da) && (1..=b).contains(&db), "{record:?}");
            // The layout table: corner i is the selector at (i + rotation) % 4 of the form.
            let values = [a, a - da, b, b - db];
            for (i, &c) in corners.iter().enumerate() {
                let s = COMPACT_QUAD_FORMS[form as usize][(i + rotation as usize) % 4];
                assert_eq!(c, values[usize::from(s)], "corner {i} of {record:?}");
            }
            let again = compact_quad_encode(corners).expect("decoded corners must encode");
            assert_eq!(compact_quad_decode(again), Ok(corners), "{record:?}");
        }
        Err(err) => match err {
            FormatError::IntegerOutOfRange {
                field: "CompactQuad.da",
                value,
                ..
            } => assert!(value == i64::from(da) && (da == 0 || da > a), "{err:?}"),
            FormatError::IntegerOutOfRange {
                field: "CompactQuad.db",
                value,
                ..
            } => {
                assert!((1..=a).contains(&da), "da is checked first: {err:?}");
                assert!(value == i64::from(db) && (db == 0 || db > b), "{err:?}");
            }
            other => panic!("unexpected compact quad error {other:?}"),
        },
    }

    // Optional corners to encode.
    let corners: Vec<u32> = (0..4).filter_map(|k| u32_at(data, 6 + 4 * k)).collect();
    let Ok(corners) = <[u32; 4]>::try_from(corners) else {
        return;
    };
    let near = |i: usize, j: usize| {
        (1..=COMPACT_QUAD_MAX_DELTA).contains(&corners[i].abs_diff(corners[j]))
    };
    let fits = corners.iter().all(|&c| c <= 0xFFFF)
        && ((near(0, 1) && near(2, 3)) || (near(1, 2) && near(3, 0)));
    match compact_quad_encode(corners) {
        Some(r) => {
            assert!(fits, "encoded {corners:?}, which does not fit");
            assert_eq!(compact_quad_decode(r), Ok(corners), "{corners:?}");
        }
        None => assert!(!fits, "refused {corners:?}, which fits"),
    }
}

// ---------------------------------------------------------------------------------------------
// blocky meshers and NoCubes
// ---------------------------------------------------------------------------------------------

/// The ids that voxel bytes `0xF0..=0xFF` stand for (low nibble): both sides of the 64-id
/// boundary of the meshers' cache of known ids, and ids past any palette.
const LARGE_IDS: [u16; 16] = [
    63, 64, 65, 69, 70, 71, 100, 255, 256, 1000, 4095, 4096, 30000, 32767, 65534, 65535,
];

/// The classes palette entries can take (2 bits each).
const CLASSES: [MaterialClass; 4] = [
    MaterialClass::Opaque,
    MaterialClass::Transparent,
    MaterialClass::ClutterBearing,
    MaterialClass::Smoothable,
];

/// A padded chunk, its palette and the mesher options decoded from fuzz bytes:
///
/// - byte 0: bits 0 and 5 the chunk size (neither: 8, bit 0: 16, bit 5: 32, both: 62, whose
///   padded rows fill a 64-bit word), bit 1 ambient occlusion, bits 2 and 4 the instruction set (neither: the detected one; bit 2: the baseline; bit 4: x86-64-v3; both:
///   x86-64-v4; a set this CPU does not run falls back to the detected one), bit 3 a wide
///   palette (opaque entries up to id 70, so ids 64..=70 are known);
/// - byte 1 (low 3 bits): palette entries `1..=n`; bytes 2-3: their classes, 2 bits each;
/// - bytes 4..: the padded voxels in storage order (x fastest), repeated cyclically (none: all
///   air). A byte below `0xF0` is id `byte % 9` (so ids past the palette are unknown); the rest
///   are [`LARGE_IDS`].
pub(crate) struct BlockyInput {
    /// The padded chunk.
    pub padded: PaddedChunk,
    /// The palette's classes.
    pub classes: BlockClasses,
    /// Ambient occlusion on.
    pub ao: bool,
    /// The instruction set to pin, if any.
    pub instruction_set: Option<InstructionSet>,
}

/// Decodes a [`BlockyInput`]; `None` for inputs shorter than the 4 header bytes.
pub(crate) fn blocky_input(data: &[u8]) -> Option<BlockyInput> {
    let [head, count, c0, c1, voxels @ ..] = data else {
        return None;
    };
    let size = [
        ChunkSize::S8,
        ChunkSize::S16,
        ChunkSize::S32,
        ChunkSize::S62,
    ][usize::from(head & 1 | (head >> 4) & 2)];
    let class_bits = u16::from_le_bytes([*c0, *c1]);
    let mut palette = MaterialPalette::new();
    for i in 0..(count & 7) {
        let class = CLASSES[usize::from(class_bits >> (2 * i)) & 3];
        palette
            .push(Material::opaque(100, 100, 100).with_class(class))
            .expect("a small palette has room");
    }
    if head & 8 != 0 {
        while palette.len() <= 70 {
            palette
                .push(Material::opaque(90, 90, 90))
                .expect("a small palette has room");
        }
    }
    let p = size.padded_edge();
    let padded = PaddedChunk::from_fn(size, |x, y, z| {
        if voxels.is_empty() {
            return BlockId::AIR;
        }
        let i = x as usize + p * (y as usize + p * z as usize);
        let b = voxels[i % voxels.len()];
        BlockId(if b < 0xF0 {
            u16::from(b % 9)
        } else {
            LARGE_IDS[usize::from(b & 15)]
        })
    });
    Some(BlockyInput {
        padded,
        classes: BlockClasses::from_palette(&palette),
        ao: head & 2 != 0,
        instruction_set: match (head & 4 != 0, head & 16 != 0) {
            (false, false) => None,
            (true, false) => Some(InstructionSet::Baseline),
            // Both bits once chose the AVX-512 set, which is gone; the corpus keeps its meaning.
            (_, true) => Some(InstructionSet::X86V3),
        },
    })
}

/// The blocky meshers on an arbitrary chunk and palette (see [`blocky_input`]):
///
/// - when no visible face belongs to an unknown id: the greedy quads and the visible-face quads
///   each cover exactly the brute-force visible faces (position, direction, id, AO) of each
///   layer, without overlap, and the visible-face quads are all 1 x 1;
/// - otherwise each fails with `UnknownBlock` naming an unknown id at a voxel that has a
///   visible face, and leaves the mesh empty;
/// - a mesher reused after both runs gives the same greedy mesh again;
/// - from the chunk's ids as a plain `u16` array (`mesh_u16`, which builds its own occupancy
///   columns), the greedy mesh or error is the same;
/// - NoCubes on the same chunk: fails exactly when the padded chunk holds an unknown id (the
///   first in storage order, as documented) and leaves both outputs empty, else makes one
///   smooth quad per owned face between a smoothable and a non-opaque voxel, with every index
///   inside the vertex buffer, and the greedy quads of the other blocks (the greedy mesher's
///   output less the smoothable blocks' quads), with counts that match its stats.
pub(crate) fn blocky_mesh(data: &[u8]) {
    let Some(input) = blocky_input(data) else {
        return;
    };
    let BlockyInput {
        padded,
        classes,
        ao,
        instruction_set,
    } = &input;
    let edge = padded.size().edge();
    let (opaque, transparent) = reference_faces(padded, classes, *ao);
    let unknown = |id: u16| id != 0 && classes.class(BlockId(id)).is_none();
    let shows_unknown = opaque.iter().chain(&transparent).any(|f| unknown(f.id));

    let mut mesher = GreedyMesher::new().with_ambient_occlusion(*ao);
    if let Some(set) = instruction_set.filter(|set| set.is_supported()) {
        mesher = mesher
            .with_instruction_set(set)
            .expect("a supported set is taken");
    }
    let mut mesh = BlockyMesh::new();
    let mut first_greedy = None;
    for (run, greedy) in [(0, true), (1, false), (2, true)] {
        let result = if greedy {
            mesher.mesh(padded, classes, &mut mesh)
        } else {
            mesher.visible_faces(padded, classes, &mut mesh)
        };
        match result {
            Ok(()) => {
                assert!(!shows_unknown, "run {run}: an unknown id's face was meshed");
                assert_eq!(
                    covered(&mesh.opaque, edge),
                    opaque,
                    "run {run}: opaque layer"
                );
                assert_eq!(
                    covered(&mesh.transparent, edge),
                    transparent,
                    "run {run}: transparent layer"
                );
                if !greedy {
                    assert_eq!(
                        mesh.len(),
                        opaque.len() + transparent.len(),
                        "visible faces are 1 x 1"
                    );
                }
            }
            Err(MeshError::UnknownBlock { id, position }) => {
                assert!(unknown(id.0), "run {run}: {id:?} is known");
                let named = opaque
                    .iter()
                    .chain(&transparent)
                    .any(|f| f.pos == position && f.id == id.0);
                assert!(
                    named,
                    "run {run}: no visible face of {id:?} at {position:?}"
                );
                assert!(mesh.is_empty(), "run {run}: partial mesh after an error");
            }
            Err(other) => panic!("run {run}: unexpected error {other:?}"),
        }
        if greedy {
            match &first_greedy {
                None => first_greedy = Some(mesh.clone()),
                Some(first) => assert_eq!(first, &mesh, "a reused mesher differs"),
            }
            // The plain-array entry builds its own occupancy columns: same result, same error,
            // with the array on a 32-byte boundary and 16 bytes past one (read another way).
            let ids: &[u16] = bytemuck::cast_slice(padded.voxels());
            let mut placed = vec![0u16; ids.len() + 24];
            let boundary = (0..16)
                .find(|&i| (placed[i..].as_ptr() as usize).is_multiple_of(32))
                .expect("a u16 array has a 32-byte boundary in its first 16 ids");
            for at in [boundary, boundary + 8] {
                placed[at..at + ids.len()].copy_from_slice(ids);
                let mut plain = BlockyMesh::new();
                let array = &placed[at..at + ids.len()];
                let plain_result = mesher.mesh_u16(array, classes, &mut plain);
                assert_eq!(plain_result, result, "run {run}: mesh_u16 answers as mesh");
                assert_eq!(plain, mesh, "run {run}: mesh_u16 meshes as mesh");
            }
        }
    }
    nocubes_check(padded, classes);
}

/// The NoCubes part of [`blocky_mesh`].
fn nocubes_check(padded: &PaddedChunk, classes: &BlockClasses) {
    let p = padded.padded_edge() as u32;
    let mut first_unknown = None;
    'scan: for z in 0..p {
        for y in 0..p {
            for x in 0..p {
                let id = padded.get(x, y, z).expect("inside the padded box");
                if !id.is_air() && classes.class(id).is_none() {
                    first_unknown = Some((id, [x, y, z]));
                    break 'scan;
                }
            }
        }
    }
    let opaque_class = |pos: [i64; 3]| {
        let id = BlockId(voxel(padded, pos));
        classes.class(id).filter(|c| c.is_opaque())
    };
    let mut smooth_faces = 0usize;
    if first_unknown.is_none() {
        let e = i64::from(padded.size().edge());
        for z in 1..=e {
            for y in 1..=e {
                for x in 1..=e {
                    for axis in 0..3 {
                        let (a, mut b) = ([x, y, z], [x, y, z]);
                        b[axis] += 1;
                        let solid = match (opaque_class(a), opaque_class(b)) {
                            (Some(c), None) | (None, Some(c)) => c,
                            _ => continue,
                        };
                        smooth_faces += usize::from(solid == MaterialClass::Smoothable);
                    }
                }
            }
        }
    }

    let (mut smooth, mut cubes) = (SmoothMesh::new(), BlockyMesh::new());
    match (
        NoCubes::new().mesh(padded, classes, &mut smooth, &mut cubes),
        first_unknown,
    ) {
        (Ok(stats), None) => {
            assert_eq!(stats.smooth_quads, smooth_faces, "smooth quads");
            assert_eq!(smooth.quad_count(), smooth_faces);
            assert_eq!(smooth.vertices().len(), stats.smooth_vertices);
            let vertices = smooth.vertices().len() as u32;
            for t in smooth.triangles() {
                assert!(
                    t.iter().all(|&i| i < vertices),
                    "triangle {t:?} past {vertices}"
                );
            }
            // The cube quads are the greedy quads of the non-smoothable blocks.
            let mut greedy = BlockyMesh::new();
            GreedyMesher::new()
                .mesh(padded, classes, &mut greedy)
                .expect("no unknown id");
            for faces in &mut greedy.opaque.faces {
                faces.retain(|q| {
                    let id = q.decode().expect("valid quad").block;
                    classes.class(id) != Some(MaterialClass::Smoothable)
                });
            }
            assert_eq!(cubes, greedy, "cube and transparent quads");
            assert_eq!(stats.cube_quads, cubes.opaque.len());
        }
        (Err(MeshError::UnknownBlock { id, position }), Some(first)) => {
            assert_eq!(
                (id, position),
                first,
                "NoCubes names the first unknown voxel"
            );
            assert!(
                smooth.is_empty() && cubes.is_empty(),
                "partial NoCubes mesh after an error"
            );
        }
        (result, first) => panic!("NoCubes gave {result:?}; first unknown voxel {first:?}"),
    }
}

// ---------------------------------------------------------------------------------------------
// SurfaceNets
// ---------------------------------------------------------------------------------------------

/// SurfaceNets on arbitrary grids. Bytes 0-2: samples per axis (`3 + byte % 8`); byte 3, bit 0:
/// the samples are raw little-endian `f32`s from bytes 4.. (any bit pattern: NaN, infinities,
/// subnormals, huge values), else `i8`s from bytes 4..; both repeated cyclically. Checks:
///
/// - `f32`: fails exactly when a sample is not finite, with the index and value of the first
///   one in storage order; otherwise one quad per owned crossing edge (lower sample in
///   `1..=d - 2` on every axis, signs differ: negative is inside), every quad index inside the
///   vertex buffer, the unpacked mesh has the same quad count, and each of its vertices lies
///   in its cell;
/// - `i8`: `mesh_i8` equals `mesh_f32` on the densities `q * I8_DENSITY_STEP` exactly, as
///   documented;
/// - a reused mesher gives the same mesh again.
pub(crate) fn smooth_density(data: &[u8]) {
    let [dx, dy, dz, mode, bytes @ ..] = data else {
        return;
    };
    let dims = [dx, dy, dz].map(|d| 3 + u32::from(d % 8));
    let shape = GridShape::new(dims).expect("3..=10 samples per axis");
    let n = shape.sample_count();
    let mut nets = SurfaceNets::new();
    let mut out = SmoothMesh::new();
    let samples: Vec<f32> = if mode & 1 != 0 {
        let words = bytes.len() / 4;
        if words == 0 {
            return;
        }
        (0..n)
            .map(|i| {
                let w = 4 * (i % words);
                f32::from_le_bytes([bytes[w], bytes[w + 1], bytes[w + 2], bytes[w + 3]])
            })
            .collect()
    } else {
        if bytes.is_empty() {
            return;
        }
        let q: Vec<i8> = (0..n).map(|i| bytes[i % bytes.len()] as i8).collect();
        let mut from_i8 = SmoothMesh::new();
        nets.mesh_i8(&q, shape, BlockId(1), &mut from_i8)
            .expect("i8 grids of a valid shape always mesh");
        let f: Vec<f32> = q.iter().map(|&v| f32::from(v) * I8_DENSITY_STEP).collect();
        nets.mesh_f32(&f, shape, BlockId(1), &mut out)
            .expect("finite grids mesh");
        assert_eq!(from_i8, out, "i8 and f32 meshes differ");
        f
    };

    let result = nets.mesh_f32(&samples, shape, BlockId(1), &mut out);
    let first_bad = samples.iter().position(|v| !v.is_finite());
    let Some(first_bad) = first_bad else {
        result.expect("finite grids mesh");
        check_nets_mesh(&samples, shape, &out, &mut nets);
        let again = out.clone();
        nets.mesh_f32(&samples, shape, BlockId(1), &mut out)
            .expect("finite grids mesh");
        assert_eq!(again, out, "a reused mesher differs");
        return;
    };
    match result {
        Err(MeshError::NonFiniteDensity { index, value }) => {
            assert_eq!(index, first_bad, "not the first non-finite sample");
            assert_eq!(value.to_bits(), samples[first_bad].to_bits());
            assert!(out.is_empty(), "partial mesh after an error");
        }
        other => panic!(
            "sample {first_bad} is {}, yet {other:?}",
            samples[first_bad]
        ),
    }
}

/// The checks of a finite grid's mesh (see [`smooth_density`]).
fn check_nets_mesh(samples: &[f32], shape: GridShape, out: &SmoothMesh, nets: &mut SurfaceNets) {
    let [dx, dy, dz] = shape.dims();
    let inside = |p: [u32; 3]| samples[shape.index(p)] < 0.0;
    let mut crossings = 0usize;
    for z in 1..dz - 1 {
        for y in 1..dy - 1 {
            for x in 1..dx - 1 {
                for axis in 0..3 {
                    let mut b = [x, y, z];
                    b[axis] += 1;
                    crossings += usize::from(inside([x, y, z]) != inside(b));
                }
            }
        }
    }
    assert_eq!(
        out.quad_count(),
        crossings,
        "one quad per owned crossing edge"
    );
    let vertices = out.vertices().len() as u32;
    for t in out.triangles() {
        assert!(
            t.iter().all(|&i| i < vertices),
            "triangle {t:?} past {vertices}"
        );
    }
    let mut raw = SmoothMeshF32::default();
    nets.mesh_f32_unpacked(samples, shape, &mut raw)
        .expect("finite grids mesh");
    assert_eq!(raw.quads.len(), crossings);
    for (position, cell) in raw.positions.iter().zip(&raw.cells) {
        for axis in 0..3 {
            let low = cell[axis] as f32;
            assert!(
                (low..=low + 1.0).contains(&position[axis]),
                "vertex {position:?} outside its cell {cell:?}"
            );
        }
    }
}
