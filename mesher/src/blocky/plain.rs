//! The plain-array input: a padded `u16` array as other meshers take it, and its occupancy
//! columns.

use alloc::vec::Vec;

use voxel_core::ChunkSize;

use super::bits::row_non_air;
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

/// Occupancy columns of a padded array of edge `p`: `out[y + p * z]` has bit `x` set iff the id
/// at `(x, y, z)` is not air. `flat` is scratch.
///
/// Rows of 64 ids (62^3 chunks) are one SIMD compare each. Shorter rows (edges 34, 18, 10)
/// would take the scalar path of [`row_non_air`] row by row, which cost 6 instructions a voxel
/// at 34 against 0.6 at 64; so the whole array is masked 64 ids at a time into `flat` (bit `i`
/// of the array at bit `i % 64` of word `i / 64`), and each row's `p` bits, which start at bit
/// `p * row`, are cut out of one or two of its words.
#[inline(always)]
pub(crate) fn build_columns(p: usize, voxels: &[u16], out: &mut Vec<u64>, flat: &mut Vec<u64>) {
    out.clear();
    if p == 64 {
        #[expect(
            clippy::redundant_closure,
            reason = "the closure is inlined into the loop; `row_non_air` passed as a function \
                      went through an outlined call per row (6 instructions, callgrind)"
        )]
        out.extend(voxels.chunks_exact(64).map(|row| row_non_air(row)));
    } else {
        build_short_columns(p, voxels, out, flat);
    }
}

/// [`build_columns`] for rows shorter than 64 ids: a call of its own, since inlined into the
/// mesher it made the 62^3 path 0.9 % slower (the mesher's other loops compiled differently).
#[inline(never)]
fn build_short_columns(p: usize, voxels: &[u16], out: &mut Vec<u64>, flat: &mut Vec<u64>) {
    flat.clear();
    #[expect(clippy::redundant_closure, reason = "as in `build_columns`")]
    flat.extend(voxels.chunks(64).map(|ids| row_non_air(ids)));
    // A row's bits may end in the last word: the word after it reads as empty.
    flat.push(0);
    let row_bits = (1u64 << p) - 1;
    out.extend((0..voxels.len() / p).map(|row| {
        let bit = p * row;
        let (word, shift) = (bit / 64, (bit % 64) as u32);
        let low = flat[word] >> shift;
        // A row starting on a word boundary takes no high part (a shift by 64 would overflow).
        let high = flat[word + 1].checked_shl(64 - shift).unwrap_or(0);
        (low | high) & row_bits
    }));
}

#[cfg(test)]
mod tests {
    use alloc::vec;

    use super::*;

    /// Every supported edge, random ids with runs of air: each row's mask is its own ids'.
    #[test]
    fn columns_match_each_row_s_ids() {
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for p in [10, 18, 34, 64] {
            let voxels: Vec<u16> = (0..p * p * p)
                .map(|_| match next() % 4 {
                    0 | 1 => 0,
                    2 => 1,
                    _ => (next() % 65_535) as u16 + 1,
                })
                .collect();
            let (mut out, mut flat) = (vec![7], vec![9]);
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
