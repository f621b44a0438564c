//! The plain-array input: a padded `u16` array as other meshers take it, and its occupancy
//! columns.

use alloc::vec::Vec;

use voxel_core::ChunkSize;

use super::bits::{masked, row_non_air};
use crate::MeshError;

/// The padded edge `p` with `p^3 == len`, for the supported chunk sizes.
pub(crate) fn padded_edge_of(len: usize) -> Result<usize, MeshError> {
    ChunkSize::ALL
        .into_iter()
        .map(ChunkSize::padded_edge)
        .find(|p| p * p * p == len)
        .ok_or(MeshError::BadShape {
            reason: "a padded u16 array must hold p^3 ids for p = 10, 18, 34 or 64",
            value: len,
        })
}

/// The occupancy of a whole padded array of edge 34 or less, 64 ids a word (39,304 ids in
/// 615 words at 34, and one more word that a row ending in the last one reads as empty).
pub(crate) type FlatColumns = [u64; FLAT_WORDS];

/// Words of [`FlatColumns`]: a power of two, so an index is kept in range by a mask.
pub(crate) const FLAT_WORDS: usize = 1024;

/// Occupancy columns of a padded array of edge `p`: `out[y + p * z]` has bit `x` set iff the id
/// at `(x, y, z)` is not air. `flat` is scratch.
///
/// Rows of 64 ids (62^3 chunks) are one SIMD compare each. Shorter rows (edges 34, 18, 10)
/// would take the scalar path of [`row_non_air`] row by row, which cost 6 instructions a voxel
/// at 34 against 0.6 at 64; so the whole array is masked 64 ids at a time into `flat` (bit `i`
/// of the array at bit `i % 64` of word `i / 64`), and each row's `p` bits, which start at bit
/// `p * row`, are cut out of one or two of its words.
#[inline(always)]
pub(crate) fn build_columns(p: usize, voxels: &[u16], out: &mut Vec<u64>, flat: &mut FlatColumns) {
    out.clear();
    match p {
        64 => {
            #[expect(
                clippy::redundant_closure,
                reason = "the closure is inlined into the loop; `row_non_air` passed as a \
                          function went through an outlined call per row (6 instructions, \
                          callgrind)"
            )]
            out.extend(voxels.chunks_exact(64).map(|row| row_non_air(row)));
        }
        34 => build_short_columns::<34>(voxels, out, flat),
        18 => build_short_columns::<18>(voxels, out, flat),
        _ => build_short_columns::<10>(voxels, out, flat),
    }
}

/// [`build_columns`] for rows of `P` ids, `P` below 64: a call of its own, since inlined into
/// the mesher it made the 62^3 path 0.9 % slower (the mesher's other loops compiled
/// differently). `P` is a constant so that a row's word and shift are a multiply and shifts.
#[inline(never)]
fn build_short_columns<const P: usize>(voxels: &[u16], out: &mut Vec<u64>, flat: &mut FlatColumns) {
    debug_assert_eq!(voxels.len(), P * P * P);
    debug_assert!((P * P * P).div_ceil(64) < FLAT_WORDS);
    let whole = voxels.chunks_exact(64);
    let tail = whole.remainder();
    let words = whole.len();
    for (word, ids) in flat.iter_mut().zip(whole) {
        *word = row_non_air(ids);
    }
    flat[masked::<FLAT_WORDS>(words)] = row_non_air(tail);
    // A row's bits may end in the last word: the word after it reads as empty.
    flat[masked::<FLAT_WORDS>(words + 1)] = 0;
    let row_bits = (1u64 << P) - 1;
    out.extend((0..P * P).map(|row| {
        let bit = P * row;
        let (word, shift) = (bit / 64, bit % 64);
        // The row's two words as one 128-bit value: one double shift (`shrd`) cuts it out.
        let pair = u128::from(flat[masked::<FLAT_WORDS>(word)])
            | u128::from(flat[masked::<FLAT_WORDS>(word + 1)]) << 64;
        (pair >> shift) as u64 & row_bits
    }));
}

#[cfg(test)]
mod tests {
    use alloc::vec;

    use super::*;

    /// Every supported edge, random ids with runs of air: each row's mask is its own ids'.
    #[test]
    fn columns_match_each_row_s_ids() {
        let mut rng = voxel_scene::rng::Rng::new(7);
        for p in [10, 18, 34, 64] {
            let voxels: Vec<u16> = (0..p * p * p)
                .map(|_| match rng.below(4) {
                    0 | 1 => 0,
                    2 => 1,
                    _ => rng.below(65_535) as u16 + 1,
                })
                .collect();
            let (mut out, mut flat) = (vec![7], alloc::boxed::Box::new([9; FLAT_WORDS]));
            build_columns(p, &voxels, &mut out, &mut flat);
            assert_eq!(out.len(), p * p, "edge {p}");
            for (row, ids) in voxels.chunks_exact(p).enumerate() {
                let want = ids
                    .iter()
                    .enumerate()
                    .fold(0u64, |m, (x, &id)| m | u64::from(id != 0) << x);
                assert_eq!(out[row], want, "edge {p}, row {row}");
            }
        }
    }
}
