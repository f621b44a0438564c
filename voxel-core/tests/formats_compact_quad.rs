//! Compact quads: every record decodes without panicking, encoding gives back the exact
//! corners of every quad that fits, and exactly the quads that fit are encoded; `SmoothQuads`
//! in its three forms.

use proptest::prelude::*;
use voxel_core::formats::compact_quad::{COMPACT_QUAD_FORMS, COMPACT_QUAD_SELECTORS};
use voxel_core::formats::{
    COMPACT_QUAD_BYTES, COMPACT_QUAD_MAX_DELTA, FormatError, SmoothQuadForm, SmoothQuads,
    compact_quad_decode, compact_quad_encode,
};

/// The record with the given fields (the documented layout).
fn record(a: u16, da: u16, b: u16, db: u16, form: u16, rotation: u16) -> [u16; 3] {
    [a, b, da | db << 6 | form << 12 | rotation << 14]
}

/// Whether `corners` fit by the definition: all at most 65,535, and the pairs (0, 1) and
/// (2, 3), or (1, 2) and (3, 0), each differ by `1..=63`.
fn fits(corners: [u32; 4]) -> bool {
    let near = |i: usize, j: usize| {
        (1..=COMPACT_QUAD_MAX_DELTA).contains(&corners[i].abs_diff(corners[j]))
    };
    corners.iter().all(|&c| c <= 0xffff)
        && ((near(0, 1) && near(2, 3)) || (near(1, 2) && near(3, 0)))
}

/// A GPU-style decode from the little-endian bytes of a record array: `u32` words, `u16`
/// halves, the selector word (what a shader does).
fn decode_like_a_shader(words: &[u32], i: usize, corner: u32) -> u32 {
    let half = |h: usize| (words[h / 2] >> (16 * (h % 2))) & 0xffff;
    let (a, b, info) = (half(3 * i), half(3 * i + 1), half(3 * i + 2));
    let (da, db) = (info & 63, (info >> 6) & 63);
    let (form, rotation) = ((info >> 12) & 3, info >> 14);
    let p = (corner + rotation) & 3;
    let s = (COMPACT_QUAD_SELECTORS >> (2 * (4 * form + p))) & 3;
    let base = if s < 2 { a } else { b };
    let delta = if s < 2 { da } else { db };
    base - if s & 1 == 1 { delta } else { 0 }
}

#[test]
fn deltas_1_and_63_fit_and_64_does_not() {
    for d in [1, 63] {
        let q = [1000, 1000 - d, 500 - d, 500];
        let r = compact_quad_encode(q).expect("fits");
        assert_eq!(compact_quad_decode(r), Ok(q));
    }
    assert_eq!(compact_quad_encode([1000, 936, 436, 500]), None);
    assert_eq!(compact_quad_encode([1000, 999, 436, 500]), None);
    assert_eq!(COMPACT_QUAD_BYTES, size_of::<[u16; 3]>());
}

#[test]
fn an_all_zero_record_is_an_error() {
    assert!(matches!(
        compact_quad_decode([0; 3]),
        Err(FormatError::IntegerOutOfRange {
            field: "CompactQuad.da",
            ..
        })
    ));
}

#[test]
fn the_shader_decode_reads_packed_records() {
    // Records of every form and rotation, back to back, read as u32 words.
    let mut records = Vec::new();
    let mut expected = Vec::new();
    for form in 0..4u16 {
        for rotation in 0..4u16 {
            let r = record(900 + form, 1 + rotation, 70, 63, form, rotation);
            expected.push(compact_quad_decode(r).unwrap());
            records.push(r);
        }
    }
    let mut bytes: Vec<u8> = bytemuck::cast_slice(&records).to_vec();
    assert_eq!(bytes.len(), 6 * records.len());
    bytes.resize(bytes.len().next_multiple_of(4), 0);
    let words: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .collect();
    for (i, corners) in expected.iter().enumerate() {
        for c in 0..4 {
            assert_eq!(decode_like_a_shader(&words, i, c), corners[c as usize]);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    #[test]
    fn every_record_decodes_or_is_an_error(r in any::<[u16; 3]>()) {
        let [a, b, info] = r.map(u32::from);
        let (da, db) = (info & 63, (info >> 6) & 63);
        match compact_quad_decode(r) {
            Ok(corners) => {
                prop_assert!(da >= 1 && da <= a && db >= 1 && db <= b);
                // Each corner is one of a, a - da, b, b - db, and re-encoding keeps them.
                let values = [a, a - da, b, b - db];
                prop_assert!(corners.iter().all(|c| values.contains(c)));
                let again = compact_quad_encode(corners);
                prop_assert!(again.is_some());
                prop_assert_eq!(compact_quad_decode(again.unwrap()), Ok(corners));
            }
            Err(_) => prop_assert!(da == 0 || da > a || db == 0 || db > b),
        }
    }

    #[test]
    fn fitting_quads_round_trip(
        a in 63u16..=u16::MAX,
        b in 63u16..=u16::MAX,
        da in 1u16..=63,
        db in 1u16..=63,
        form in 0u16..4,
        rotation in 0u16..4,
    ) {
        let values = [a, a - da, b, b - db].map(u32::from);
        let cycle = COMPACT_QUAD_FORMS[usize::from(form)].map(|s| values[usize::from(s)]);
        let corners: [u32; 4] =
            std::array::from_fn(|i| cycle[(i + usize::from(rotation)) % 4]);
        prop_assert_eq!(
            compact_quad_decode(record(a, da, b, db, form, rotation)),
            Ok(corners)
        );
        let r = compact_quad_encode(corners);
        prop_assert!(r.is_some());
        prop_assert_eq!(compact_quad_decode(r.unwrap()), Ok(corners));
    }

    #[test]
    fn exactly_the_quads_that_fit_are_encoded(
        base in 0u32..70_000,
        offsets in [0u32..140, 0u32..140, 0u32..140, 0u32..140],
    ) {
        let corners = offsets.map(|o| base + o);
        match compact_quad_encode(corners) {
            Some(r) => {
                prop_assert!(fits(corners));
                prop_assert_eq!(compact_quad_decode(r), Ok(corners));
            }
            None => prop_assert!(!fits(corners)),
        }
    }
}

#[test]
fn smooth_quads_in_every_form() {
    let records = [[5u16, 9, 1 | 2 << 6 | 2 << 12], [70, 64, 63 | 1 << 6]];
    let narrow = [[0u16, 1, 2, 3], [7, 6, 5, 4]];
    let wide = [[0u32, 1, 2, 70_000]];
    let compact = SmoothQuads::Compact(&records);
    assert_eq!(compact.get(0), Some([5, 4, 9, 7]));
    assert_eq!(compact.get(2), None);
    assert_eq!((compact.bytes().len(), compact.word_len()), (12, 3));
    let odd = SmoothQuads::Compact(&records[..1]);
    assert_eq!((odd.bytes().len(), odd.word_len()), (6, 2));
    let u16s = SmoothQuads::U16(&narrow);
    assert_eq!(
        u16s.iter().collect::<Vec<_>>(),
        [[0, 1, 2, 3], [7, 6, 5, 4]]
    );
    assert_eq!((u16s.word_len(), u16s.quad_bytes()), (4, 8));
    let u32s = SmoothQuads::U32(&wide);
    assert_eq!(u32s.get(0), Some([0, 1, 2, 70_000]));
    assert_eq!((u32s.word_len(), u32s.quad_bytes()), (4, 16));
    for (quads, form) in [
        (compact, SmoothQuadForm::Compact),
        (u16s, SmoothQuadForm::U16),
        (u32s, SmoothQuadForm::U32),
    ] {
        assert_eq!(quads.form(), form);
        assert_eq!(quads.bytes().len(), form.quad_bytes() * quads.len());
    }
    // A record that does not decode is skipped, not a panic.
    let bad = [[5u16, 9, 0]];
    assert_eq!(SmoothQuads::Compact(&bad).get(0), None);
    assert_eq!(SmoothQuads::Compact(&bad).iter().count(), 0);
    assert!(SmoothQuads::default().is_empty());
    assert_eq!(SmoothQuads::default().form(), SmoothQuadForm::Compact);
}
