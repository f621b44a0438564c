//! Compact quads: the 4 vertex indices of a smooth-mesh quad in 6 bytes (`[u16; 3]`), for
//! quads whose corners are two pairs of nearby indices.
//!
//! # Why it fits
//!
//! A SurfaceNets quad joins the vertices of the 4 cells around a crossing grid edge, and those
//! vertices are numbered in cell scan order (x fastest, then y, then z). Going round the quad,
//! its corners are two pairs of neighbouring cells one step apart along x or y (cells `c` and
//! `c - x`, or `c` and `c - y`), and the two pairs are one step apart along the third axis. The
//! two cells of a pair are close in scan order: `c - x` has the index just below `c`, and
//! `c - y` is at most one row of cells (`dx - 1`) below. So with `a` and `b` the larger index
//! of each pair, the quad is `a`, `b` and two small deltas `da`, `db` (`1..=63` for grids of up
//! to 64 samples a row, every chunk grid), plus which of the 16 cyclic layouts the corners
//! have.
//!
//! # Layout
//!
//! Three `u16` (little-endian, 6 bytes, no padding):
//!
//! ```text
//! u16 0: a            (0..=65535)
//! u16 1: b            (0..=65535)
//! u16 2: bit 0       6       12     14        16
//!            +-------+-------+------+---------+
//!            |  da   |  db   | form | rotation|
//!            +-------+-------+------+---------+
//! ```
//!
//! | field    | bits        | range  | meaning                                              |
//! | -------- | ----------- | ------ | ---------------------------------------------------- |
//! | a        | u16 0       | u16    | the larger index of the first pair                   |
//! | b        | u16 1       | u16    | the larger index of the second pair                  |
//! | da       | u16 2, 0..6 | 1..=63 | the first pair's other index is `a - da` (`da <= a`) |
//! | db       | u16 2, 6..12| 1..=63 | the second pair's other index is `b - db` (`db <= b`)|
//! | form     | u16 2, 12..14 | 0..4 | the cycle `C` of the 4 indices, from `a` ([`COMPACT_QUAD_FORMS`]) |
//! | rotation | u16 2, 14..16 | 0..4 | corner `i` of the quad is `C[(i + rotation) % 4]`    |
//!
//! The forms (`a' = a - da`, `b' = b - db`) are every way to go round 4 corners in which each
//! pair is two neighbouring corners:
//!
//! | form | cycle `C`          |
//! | ---- | ------------------ |
//! | 0    | `[a, b, b', a']`   |
//! | 1    | `[a, a', b', b]`   |
//! | 2    | `[a, a', b, b']`   |
//! | 3    | `[a, b', b, a']`   |
//!
//! Decoding gives back exactly the 4 corners that were encoded, in their order (so the first
//! corner and the winding, and with them the split into two triangles, are kept).
//!
//! [`compact_quad_encode`] takes the pairs (corner 0, corner 1) and (corner 2, corner 3) when
//! both fit, else (1, 2) and (3, 0), else gives up (the caller stores the quad in a wider
//! form). Several records can stand for one quad (swapping the roles of the two pairs, for
//! one); [`compact_quad_decode`] accepts all of them. It rejects only the records that no
//! quad gives: a delta of 0, or one larger than its base index (the index would be negative).
//!
//! # On the GPU
//!
//! A record is 6 bytes, which no WGSL struct can be (a `u32` member aligns it to 4), so a
//! shader reads a buffer of them as `array<u32>`: `u16` number `h` is
//! `(words[h / 2] >> (16 * (h % 2))) & 0xffff`, and record `i` is `u16`s `3 i .. 3 i + 3`.
//! Corner `i` is then [`COMPACT_QUAD_SELECTORS`]' selector `s` for position
//! `(i + rotation) % 4` of `form`: `a` or `b` (`s < 2` or not) minus `da` or `db` when `s` is
//! odd. A buffer of `n` records is `6 n` bytes; round it up to a multiple of 4 for a binding.

use super::FormatError;

/// The largest delta `da` or `db` a compact quad holds (6 bits).
pub const COMPACT_QUAD_MAX_DELTA: u32 = 63;

/// Size of one record in bytes.
pub const COMPACT_QUAD_BYTES: usize = 6;

/// The cycle of each form as selectors: `0` = `a`, `1` = `a - da`, `2` = `b`, `3` = `b - db`.
pub const COMPACT_QUAD_FORMS: [[u8; 4]; 4] = [
    [0, 2, 3, 1], // [a, b, b', a']
    [0, 1, 3, 2], // [a, a', b', b]
    [0, 1, 2, 3], // [a, a', b, b']
    [0, 3, 2, 1], // [a, b', b, a']
];

/// [`COMPACT_QUAD_FORMS`] in one word for shaders: the selector of position `p` of form `f`
/// is `(COMPACT_QUAD_SELECTORS >> (2 * (4 * f + p))) & 3`.
pub const COMPACT_QUAD_SELECTORS: u32 = {
    let mut word = 0;
    let mut f = 0;
    while f < 4 {
        let mut p = 0;
        while p < 4 {
            word |= (COMPACT_QUAD_FORMS[f][p] as u32) << (2 * (4 * f + p));
            p += 1;
        }
        f += 1;
    }
    word
};

/// `form | rotation << 2` of the record for corners `[x0, x1, x2, x3]` with the pairs
/// `(x0, x1)` and `(x2, x3)`, 4 bits for each case `(x0 > x1) << 1 | (x2 > x3)`:
///
/// - case 0, `x0 < x1, x2 < x3`: `a = x1, b = x3`, corners `[a', a, b', b]`, which is form 3
///   `[a, b', b, a']` from position 3: rotation 3;
/// - case 1, `x0 < x1, x2 > x3`: `a = x1, b = x2`, `[a', a, b, b']` = form 0
///   `[a, b, b', a']` from position 3: rotation 3;
/// - case 2, `x0 > x1, x2 < x3`: `a = x0, b = x3`, `[a, a', b', b]`: form 1, rotation 0;
/// - case 3, `x0 > x1, x2 > x3`: `a = x0, b = x2`, `[a, a', b, b']`: form 2, rotation 0.
const PAIRS_01_23: u32 = {
    // (form, rotation) per case.
    let cases: [(u32, u32); 4] = [(3, 3), (0, 3), (1, 0), (2, 0)];
    let mut word = 0;
    let mut case = 0;
    while case < 4 {
        word |= (cases[case].0 | cases[case].1 << 2) << (4 * case);
        case += 1;
    }
    word
};

/// Packs the quad `corners` into a compact record, or `None` when it does not fit: an index
/// above 65,535, or neither pairing of neighbouring corners has both deltas in
/// `1..=`[`COMPACT_QUAD_MAX_DELTA`] (see the [module docs](self)).
///
/// Branch-free except for that final answer, so it costs the same whichever pairing and
/// layout the quad has.
#[inline]
pub fn compact_quad_encode(corners: [u32; 4]) -> Option<[u16; 3]> {
    let [q0, q1, q2, q3] = corners;
    let fits = |d: u32| d.wrapping_sub(1) < COMPACT_QUAD_MAX_DELTA;
    let first = fits(q0.abs_diff(q1)) & fits(q2.abs_diff(q3));
    let second = fits(q1.abs_diff(q2)) & fits(q3.abs_diff(q0));
    // The second pairing is the first on the corners rotated by one: `x = [q1, q2, q3, q0]`,
    // so corner `i` is `x[i - 1]` and the rotation is one less.
    // Selects with a mask, not a branch: which pairing fits is unpredictable.
    let keep = u32::from(first).wrapping_neg();
    let pick = |p: u32, r: u32| (p & keep) | (r & !keep);
    let x = [pick(q0, q1), pick(q1, q2), pick(q2, q3), pick(q3, q0)];
    let back = u32::from(!first);
    let (da, db) = (x[0].abs_diff(x[1]), x[2].abs_diff(x[3]));
    let case = u32::from(x[0] > x[1]) << 1 | u32::from(x[2] > x[3]);
    let code = (PAIRS_01_23 >> (4 * case)) & 0xf;
    let rotation = ((code >> 2) + 4 - back) & 3;
    let info = da | db << 6 | (code & 3) << 12 | rotation << 14;
    let record = [x[0].max(x[1]), x[2].max(x[3]), info];
    let in_range = (q0 | q1 | q2 | q3) <= 0xffff;
    if (first | second) & in_range {
        Some(record.map(|v| v as u16))
    } else {
        None
    }
}

/// The 4 corners of a compact record, exactly as they were encoded.
///
/// Fails with [`FormatError::IntegerOutOfRange`] (field `"CompactQuad.da"` or
/// `"CompactQuad.db"`) when a delta is 0 or larger than its base index; every other bit
/// pattern decodes. Never panics.
#[inline]
pub fn compact_quad_decode(record: [u16; 3]) -> Result<[u32; 4], FormatError> {
    let [a, b, info] = record.map(u32::from);
    let da = info & COMPACT_QUAD_MAX_DELTA;
    let db = (info >> 6) & COMPACT_QUAD_MAX_DELTA;
    let check = |field: &'static str, d: u32, base: u32| {
        if d == 0 || d > base {
            Err(FormatError::IntegerOutOfRange {
                field,
                value: d.into(),
                min: 1,
                max: base.min(COMPACT_QUAD_MAX_DELTA).into(),
            })
        } else {
            Ok(base - d)
        }
    };
    let values = [
        a,
        check("CompactQuad.da", da, a)?,
        b,
        check("CompactQuad.db", db, b)?,
    ];
    let form = (info >> 12) & 3;
    let rotation = info >> 14;
    Ok(core::array::from_fn(|i| {
        let p = (i as u32 + rotation) & 3;
        values[((COMPACT_QUAD_SELECTORS >> (2 * (4 * form + p))) & 3) as usize]
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The record with the given fields.
    fn record(a: u16, da: u16, b: u16, db: u16, form: u16, rotation: u16) -> [u16; 3] {
        [a, b, da | db << 6 | form << 12 | rotation << 14]
    }

    #[test]
    fn every_form_and_rotation_decodes_to_its_cycle() {
        let (a, b) = (1000u32, 2000u32);
        for (da, db) in [(1, 1), (1, 63), (63, 1), (63, 63), (17, 5)] {
            let values = [a, a - da, b, b - db];
            for (form, selectors) in COMPACT_QUAD_FORMS.iter().enumerate() {
                let cycle = selectors.map(|s| values[usize::from(s)]);
                for rotation in 0..4 {
                    let r = record(
                        a as u16,
                        da as u16,
                        b as u16,
                        db as u16,
                        form as u16,
                        rotation as u16,
                    );
                    let corners: [u32; 4] = core::array::from_fn(|i| cycle[(i + rotation) % 4]);
                    assert_eq!(compact_quad_decode(r), Ok(corners));
                    // The encoder may pick another record, which decodes to the same corners.
                    let e = compact_quad_encode(corners).expect("fits");
                    assert_eq!(compact_quad_decode(e), Ok(corners));
                }
            }
        }
    }

    #[test]
    fn selectors_word_matches_the_table() {
        for (f, form) in COMPACT_QUAD_FORMS.iter().enumerate() {
            for (p, &s) in form.iter().enumerate() {
                assert_eq!(
                    (COMPACT_QUAD_SELECTORS >> (2 * (4 * f + p))) & 3,
                    u32::from(s)
                );
            }
        }
    }

    #[test]
    fn misfits_are_refused() {
        // A delta of 64 in either pairing.
        assert_eq!(compact_quad_encode([164, 100, 3, 2]), None);
        assert_eq!(compact_quad_encode([100, 36, 200, 136]), None);
        // 63 fits, in either pairing.
        assert!(compact_quad_encode([163, 100, 3, 2]).is_some());
        assert!(compact_quad_encode([2, 163, 100, 3]).is_some());
        // Pairs must be neighbours in the cycle: 10-9 and 200-199 facing each other do not fit.
        assert_eq!(compact_quad_encode([10, 200, 9, 199]), None);
        // A pair of repeated corners (delta 0), and indices past u16.
        assert_eq!(compact_quad_encode([5, 5, 100, 99]), None);
        assert_eq!(compact_quad_encode([65536, 65535, 3, 2]), None);
        assert!(compact_quad_encode([65535, 65534, 3, 2]).is_some());
    }

    #[test]
    fn bad_deltas_are_errors() {
        assert!(matches!(
            compact_quad_decode(record(5, 0, 9, 1, 0, 0)),
            Err(FormatError::IntegerOutOfRange {
                field: "CompactQuad.da",
                value: 0,
                ..
            })
        ));
        assert!(matches!(
            compact_quad_decode(record(5, 1, 9, 10, 0, 0)),
            Err(FormatError::IntegerOutOfRange {
                field: "CompactQuad.db",
                value: 10,
                ..
            })
        ));
        assert_eq!(
            compact_quad_decode(record(5, 5, 9, 9, 2, 0)),
            Ok([5, 0, 9, 0])
        );
    }
}
