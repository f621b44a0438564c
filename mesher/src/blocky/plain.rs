//! The plain-array input: a padded `u16` array as other meshers take it, and its occupancy
//! columns.

use core::ops::{Deref, DerefMut};

use voxel_core::ChunkSize;

use super::aligned::Words;
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
/// 615 words at 34, and one more word that a row ending in the last one reads as empty), from
/// a cache line on, as the column kernels write it with 32-byte stores.
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(crate) struct FlatColumns(pub [u64; FLAT_WORDS]);

impl Deref for FlatColumns {
    type Target = [u64; FLAT_WORDS];

    fn deref(&self) -> &[u64; FLAT_WORDS] {
        &self.0
    }
}

impl DerefMut for FlatColumns {
    fn deref_mut(&mut self) -> &mut [u64; FLAT_WORDS] {
        &mut self.0
    }
}

/// Words of [`FlatColumns`]: a power of two, so an index is kept in range by a mask.
pub(crate) const FLAT_WORDS: usize = 1024;

/// `[f(0), f(1), ..., f(31)]`, written out: the compiler does not unroll a loop of 32 rows
/// (`core::array::from_fn` or a `for`), and unrolled every row's word and shift is a constant.
macro_rules! each_of_32 {
    (|$r:ident| $e:expr) => {{
        let f = |$r: usize| $e;
        [
            f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7), f(8), f(9), f(10), f(11), f(12),
            f(13), f(14), f(15), f(16), f(17), f(18), f(19), f(20), f(21), f(22), f(23), f(24),
            f(25), f(26), f(27), f(28), f(29), f(30), f(31),
        ]
    }};
}

/// Occupancy columns of a padded array of edge `p`: `out[y + p * z]` has bit `x` set iff the id
/// at `(x, y, z)` is not air. `flat` is scratch. The portable copy; `build_columns_x86_v3`
/// (in `plain_x86`) gives the same columns with AVX2 kernels.
///
/// Rows of 64 ids (62^3 chunks) are one SIMD compare each. Shorter rows (edges 34, 18, 10)
/// would take the scalar path of [`row_non_air`] row by row, many times the work per voxel of
/// a 64-id compare; so the whole array is masked 64 ids at a time into `flat` (bit `i`
/// of the array at bit `i % 64` of word `i / 64`), and each row's `p` bits, which start at bit
/// `p * row`, are cut out of one or two of its words (see [`cut_rows`]).
///
/// Returns false, with `out` not written, when every id of a short array is air: that is
/// known from the flat mask before any row is cut, and empty chunks are the most common ones.
/// Otherwise true (the mesher's own check over the columns finds an empty 62^3 chunk).
#[inline(always)]
pub(crate) fn build_columns(
    p: usize,
    voxels: &[u16],
    out: &mut Words,
    flat: &mut FlatColumns,
) -> bool {
    match p {
        64 => {
            let rows = voxels.as_chunks::<64>().0;
            for (column, row) in out.sized(rows.len()).iter_mut().zip(rows) {
                *column = row_non_air(row);
            }
            true
        }
        34 => short_columns_portable::<34>(voxels, out, flat),
        18 => short_columns_portable::<18>(voxels, out, flat),
        _ => short_columns_portable::<10>(voxels, out, flat),
    }
}

/// The columns of an array of edge `P` below 64 on the portable code path: a call of its own,
/// since inlined into the mesher it changes how the mesher's other loops compile, and slows
/// the 62^3 path that never runs it.
#[inline(never)]
fn short_columns_portable<const P: usize>(
    voxels: &[u16],
    out: &mut Words,
    flat: &mut FlatColumns,
) -> bool {
    let (whole, tail) = voxels.as_chunks::<64>();
    debug_assert_eq!(whole.len() * 64 + tail.len(), P * P * P);
    for (word, ids) in flat.iter_mut().zip(whole) {
        *word = row_non_air(ids);
    }
    close_flat(whole.len(), tail, flat);
    if flat[..=whole.len()].iter().fold(0, |any, &w| any | w) == 0 {
        return false;
    }
    cut_rows::<P>(flat, out.sized(P * P));
    true
}

/// Closes the flat mask of an array whose first `words` words are written: the word after
/// them gets the occupancy of `tail`, the ids after those, and the word after that is empty (a
/// row's bits may end in the last word, and a cut reads the word after it). Returns whether
/// `tail` holds an id that is not air.
#[inline(always)]
pub(crate) fn close_flat(words: usize, tail: &[u16], flat: &mut FlatColumns) -> bool {
    debug_assert!(words + 2 <= FLAT_WORDS);
    let last = row_non_air(tail);
    flat[masked::<FLAT_WORDS>(words)] = last;
    flat[masked::<FLAT_WORDS>(words + 1)] = 0;
    last != 0
}

/// The `P * P` rows of an array of edge `P` below 64 into `out`, cut from `flat`, its
/// occupancy 64 ids a word, closed by [`close_flat`].
///
/// `P` is a constant and even, so 32 rows take exactly `P / 2` words: each group of 32 rows is
/// cut out of one slice of `P / 2 + 1` words (one bounds check), unrolled, with every row's
/// word and shift a constant, and a row costs about two loads, a double shift (`shrd`), a mask
/// and a store. The last `P * P % 32` rows are cut the same way one by one.
#[inline(always)]
pub(crate) fn cut_rows<const P: usize>(flat: &FlatColumns, out: &mut [u64]) {
    debug_assert!(P.is_multiple_of(2) && out.len() == P * P);
    let row_bits = (1u64 << P) - 1;
    // The `P` bits from bit `bit` of `words`.
    let cut = |words: &[u64], bit: usize| {
        let pair = u128::from(words[bit / 64]) | u128::from(words[bit / 64 + 1]) << 64;
        (pair >> (bit % 64)) as u64 & row_bits
    };
    let (groups, rest) = out.as_chunks_mut::<32>();
    for (g, rows) in groups.iter_mut().enumerate() {
        let words = &flat[g * (P / 2)..][..P / 2 + 1];
        *rows = each_of_32!(|r| cut(words, P * r));
    }
    let first = P * P - rest.len();
    for (r, row) in rest.iter_mut().enumerate() {
        *row = cut(&flat[..], P * (first + r));
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use super::*;

    /// Words holding `words`, as a mesher's scratch left by an earlier chunk.
    fn words_of(words: &[u64]) -> Words {
        let mut out = Words::default();
        out.sized(words.len()).copy_from_slice(words);
        out
    }

    /// A flat mask of `word`s, as a mesher's scratch left by an earlier chunk.
    fn flat_of(word: u64) -> alloc::boxed::Box<FlatColumns> {
        alloc::boxed::Box::new(FlatColumns([word; FLAT_WORDS]))
    }

    /// Every supported edge, random ids with runs of air and ids across the 16-bit range: each
    /// row's mask is its own ids', from every builder this CPU runs. The buffers are reused, as
    /// a mesher does: across sizes and at one size twice in a row (then they are overwritten,
    /// not resized).
    #[test]
    fn columns_match_each_row_s_ids() {
        for (name, build) in builders() {
            let mut rng = voxel_scene::rng::Rng::new(7);
            let (mut out, mut flat) = (words_of(&[7]), flat_of(9));
            for p in [10, 18, 34, 34, 64, 64, 10] {
                let voxels: Vec<u16> = (0..p * p * p)
                    .map(|_| match rng.below(4) {
                        0 | 1 => 0,
                        2 => 1,
                        _ => rng.below(65_535) as u16 + 1,
                    })
                    .collect();
                let want: Vec<u64> = voxels
                    .chunks_exact(p)
                    .map(|ids| {
                        ids.iter()
                            .enumerate()
                            .fold(0u64, |m, (x, &id)| m | u64::from(id != 0) << x)
                    })
                    .collect();
                assert!(build(p, &voxels, &mut out, &mut flat), "{name}, edge {p}");
                assert_eq!(*out, want[..], "{name}, edge {p}");
            }
        }
    }

    /// The column builders this CPU runs: the portable one, and the x86-64-v3 one where the CPU
    /// has AVX2 (else the test says so on stderr).
    fn builders() -> Vec<(&'static str, Builder)> {
        let mut all: Vec<(&'static str, Builder)> = vec![("portable", build_columns)];
        #[cfg(target_arch = "x86_64")]
        if crate::instruction_set::x86_v3_or_skip("build_columns_x86_v3") {
            all.push(("x86-64-v3", build_columns_x86_v3_checked));
        }
        all
    }

    /// A column builder's signature.
    type Builder = fn(usize, &[u16], &mut Words, &mut FlatColumns) -> bool;

    /// `build_columns_x86_v3` as a safe function, for [`builders`], which lists it only on a
    /// CPU with AVX2.
    #[cfg(target_arch = "x86_64")]
    fn build_columns_x86_v3_checked(
        p: usize,
        voxels: &[u16],
        out: &mut Words,
        flat: &mut FlatColumns,
    ) -> bool {
        assert!(crate::InstructionSet::X86V3.is_supported());
        #[expect(
            unsafe_code,
            reason = "calls the x86-64-v3 copy on a CPU checked to run it"
        )]
        // SAFETY: `X86V3.is_supported()` found every feature the copy is compiled for.
        unsafe {
            super::super::plain_x86::build_columns_x86_v3(p, voxels, out, flat)
        }
    }

    /// An all-air array below 64 is found from the flat mask: false, and the columns are not
    /// cut. One solid id anywhere gives true and its column: the first id, one in the middle,
    /// and the last (in the flat mask's tail word at every short edge).
    #[test]
    fn an_all_air_array_is_found_before_its_rows_are_cut() {
        for (name, build) in builders() {
            for p in [10, 18, 34] {
                let mut air = vec![0u16; p * p * p];
                let (mut out, mut flat) = (words_of(&[7; 3]), flat_of(9));
                assert!(!build(p, &air, &mut out, &mut flat), "{name}, edge {p}");
                assert_eq!(*out, [7; 3], "{name}, edge {p}: nothing cut");
                for at in [0, air.len() / 2 + 1, air.len() - 1] {
                    air.fill(0);
                    air[at] = 3;
                    assert!(
                        build(p, &air, &mut out, &mut flat),
                        "{name}, edge {p}, {at}"
                    );
                    assert_eq!(out.len(), p * p);
                    for (row, &column) in out.iter().enumerate() {
                        let want = if row == at / p { 1 << (at % p) } else { 0 };
                        assert_eq!(column, want, "{name}, edge {p}, solid id {at}, row {row}");
                    }
                }
            }
        }
    }
}
