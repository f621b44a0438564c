//! The plain-array input's occupancy columns compiled for x86-64-v3: the same columns as
//! [`build_columns`](super::plain::build_columns), with AVX2 kernels.
//!
//! # Why the kernels look like this
//!
//! An AVX2 register holds 16 ids. Two are packed to 32 bytes with signed saturation (a
//! non-zero `i16` stays non-zero), compared with zero and turned into 32 air bits by
//! `vpmovmskb`. The pack works within each 128-bit half of the registers, so the 32 bits come
//! out in *lane order*: ids 0-7, 16-23, 8-15, 24-31, one byte each. Putting them in id order
//! with a cross-lane permute per pack would be half the kernel's shuffle work, and Intel cores
//! run both the packs and the permutes on one port: the kernel would be bound by that port.
//!
//! So [`air_in_lane_order`] stores the bits as they come, two `u32`s per 64 ids, and one pass
//! ([`to_id_order_non_air`]) swaps the middle two bytes of every `u32` with one in-lane byte
//! shuffle per 32 bytes, and inverts air into occupancy.
//!
//! # Arrays 16 bytes past a 32-byte boundary
//!
//! The kernel loads 32 bytes at a time from the array's start. An array that starts 16 bytes
//! past a 32-byte boundary, as `malloc` hands out many blocks (every block it maps from the
//! system, such as a 62^3 chunk's 512 KiB), then splits every second load across two cache
//! lines, and its columns took 1.4 to 1.5 times as long. Such an array is read from its ninth
//! id on, every load aligned ([`non_air_words_from_ninth`]). Its words are then a byte
//! ahead of the array's: the id-order pass ([`to_id_order_non_air`]) reads each word from one
//! byte before, and since that moves the swapped bytes too, it swaps bytes 2 and 3, and 6 and
//! 7, of every word instead.
//!
//! At padded edge 34 each row of 34 bits is then cut out of the flat mask four rows a step
//! ([`cut_34_rows`]): four rows are 136 bits, 17 bytes, and row `k` of the four starts at
//! byte `4 k`, bit `2 k`; so one 32-byte load, a dword permute (`0, 1, 1, 2, 2, 3, 3, 4`), a
//! variable shift by `0, 2, 4, 6` and a mask give the four rows.

#[cfg(target_feature = "sse2")]
use core::arch::x86_64::{
    __m256i, _mm256_and_si256, _mm256_cmpeq_epi8, _mm256_movemask_epi8, _mm256_or_si256,
    _mm256_packs_epi16, _mm256_permutevar8x32_epi32, _mm256_set1_epi8, _mm256_set1_epi64x,
    _mm256_setr_epi8, _mm256_setr_epi32, _mm256_setr_epi64x, _mm256_setzero_si256,
    _mm256_shuffle_epi8, _mm256_srlv_epi64, _mm256_testz_si256, _mm256_xor_si256,
};

use super::aligned::Words;
#[cfg(target_feature = "sse2")]
use super::bits::{masked, row_non_air};
use super::plain::FlatColumns;
#[cfg(not(target_feature = "sse2"))]
use super::plain::build_columns;
#[cfg(target_feature = "sse2")]
use super::plain::{FLAT_WORDS, close_flat, cut_rows};

/// [`build_columns`](super::plain::build_columns) compiled for x86-64-v3, with the AVX2
/// kernels of this module. On an x86-64 target without SSE (soft float, as
/// `x86_64-unknown-none`), which cannot hold AVX2 vectors, the portable builder.
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
pub(crate) fn build_columns_x86_v3(
    p: usize,
    voxels: &[u16],
    out: &mut Words,
    flat: &mut FlatColumns,
) -> bool {
    #[cfg(not(target_feature = "sse2"))]
    return build_columns(p, voxels, out, flat);
    #[cfg(target_feature = "sse2")]
    match p {
        64 => {
            let columns = out.sized(64 * 64);
            if starts_at_16_of_32(voxels) {
                non_air_words_from_ninth(voxels, columns);
            } else {
                let rows = voxels.as_chunks::<64>().0;
                air_in_lane_order(rows, columns);
                to_id_order_non_air::<0>(columns, rows.len());
            }
            true
        }
        34 => short_columns::<34>(voxels, out, flat),
        18 => short_columns::<18>(voxels, out, flat),
        _ => short_columns::<10>(voxels, out, flat),
    }
}

/// The columns of an array of edge `P` below 64: the flat mask 64 ids a word, put in id
/// order, then the rows cut out of it. False, with nothing cut, when every id is air.
#[cfg(target_feature = "sse2")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline(never)]
fn short_columns<const P: usize>(voxels: &[u16], out: &mut Words, flat: &mut FlatColumns) -> bool {
    if starts_at_16_of_32(voxels) {
        let words = (P * P * P).div_ceil(64);
        let any = non_air_words_from_ninth(voxels, &mut flat[..words]);
        // The empty word after the last, which the row cuts read.
        flat[masked::<FLAT_WORDS>(words)] = 0;
        if !any {
            return false;
        }
    } else {
        let (whole, tail) = voxels.as_chunks::<64>();
        debug_assert_eq!(whole.len() * 64 + tail.len(), P * P * P);
        let words = &mut flat[..whole.len()];
        air_in_lane_order(whole, words);
        let any = to_id_order_non_air::<0>(words, whole.len());
        if !close_flat(whole.len(), tail, flat) && !any {
            return false;
        }
    }
    let out = out.sized(P * P);
    if P == 34 {
        cut_34_rows(flat, out);
    } else {
        cut_rows::<P>(flat, out);
    }
    true
}

/// Whether `voxels` starts 16 bytes past a 32-byte boundary (see the [module docs](self)).
#[cfg(target_feature = "sse2")]
#[inline(always)]
fn starts_at_16_of_32(voxels: &[u16]) -> bool {
    voxels.as_ptr() as usize % 32 == 16
}

/// The occupancy of `voxels` in id order, 64 ids a word, into `out` (exactly one word per 64
/// ids or part of 64), read from the ninth id on so that every load of an array that starts
/// 16 bytes past a 32-byte boundary is aligned (see the [module docs](self)). Returns whether
/// any id is not air.
///
/// The kernel writes the air of ids `8 + 64 k ..` in lane order to `out[k + 1]`, and the air
/// of ids `0..8` is the top byte of `out[0]`. Word `k` of the array is then the eight bytes
/// from byte `8 k + 7` of `out`: the top byte of the word before, then seven of this one.
#[cfg(target_feature = "sse2")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn non_air_words_from_ninth(voxels: &[u16], out: &mut [u64]) -> bool {
    let (first, rest) = voxels.split_at(8.min(voxels.len()));
    let (whole, tail) = rest.as_chunks::<64>();
    let n = whole.len();
    debug_assert_eq!(out.len(), n + 1, "one word per 64 ids or part of 64");
    debug_assert!(tail.len() <= 56, "the last word holds the tail");
    air_in_lane_order(whole, &mut out[1..=n]);
    // The air of the first eight ids, as the top byte of a word before the first.
    out[0] = !row_non_air(first) << 56;
    // The last word first: the top byte of the last word the kernel wrote, then the tail,
    // before the pass below overwrites anything it reads.
    let top = !out[n] >> 56;
    let last = row_non_air(tail);
    let any = to_id_order_non_air::<7>(out, n);
    out[n] = top | (last << 8);
    any || out[n] != 0
}

/// The air of every 64 ids of `rows` into the word of `out` at the same index, in lane order
/// (see the [module docs](self)): the `u32` of ids 0-31 first, then that of ids 32-63, each
/// with its middle two bytes swapped. `out` holds at least as many words as `rows` rows.
#[cfg(target_feature = "sse2")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn air_in_lane_order(rows: &[[u16; 64]], out: &mut [u64]) {
    let air = |row: &[u16; 64]| -> [u32; 2] {
        let sixteen = |k: usize| -> __m256i {
            let ids: [u16; 16] = core::array::from_fn(|j| row[16 * k + j]);
            bytemuck::cast(ids)
        };
        let half = |k: usize| -> u32 {
            let packed = _mm256_packs_epi16(sixteen(k), sixteen(k + 1));
            _mm256_movemask_epi8(_mm256_cmpeq_epi8(packed, _mm256_setzero_si256())) as u32
        };
        [half(0), half(2)]
    };
    let out: &mut [[u32; 2]] = bytemuck::cast_slice_mut(&mut out[..rows.len()]);
    // Four rows a step: one row a step, the loop's own counting is a large share of the
    // kernel's instructions.
    let (rows4, rows_rest) = rows.as_chunks::<4>();
    let (out4, out_rest) = out.as_chunks_mut::<4>();
    for (four, rows) in out4.iter_mut().zip(rows4) {
        *four = [air(&rows[0]), air(&rows[1]), air(&rows[2]), air(&rows[3])];
    }
    for (word, row) in out_rest.iter_mut().zip(rows_rest) {
        *word = air(row);
    }
}

/// Turns words of air bits in lane order (from [`air_in_lane_order`]) into `n` words of
/// occupancy in id order, in place: word `k` is read from byte `8 k + AHEAD` of `words` and
/// written to word `k`. `AHEAD` is 0 for words where the kernel wrote them, or 7 for an array
/// read from its ninth id on (see [`non_air_words_from_ninth`]), whose swapped bytes then sit
/// one byte further up. Returns whether any bit is set (some id is not air).
#[cfg(target_feature = "sse2")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn to_id_order_non_air<const AHEAD: usize>(words: &mut [u64], n: usize) -> bool {
    const { assert!(AHEAD == 0 || AHEAD == 7) };
    // Bytes 0, 2, 1, 3 of every `u32` (or 0, 1, 3, 2 one byte up): each swap is its own
    // inverse.
    let swap = if AHEAD == 0 {
        _mm256_setr_epi8(
            0, 2, 1, 3, 4, 6, 5, 7, 8, 10, 9, 11, 12, 14, 13, 15, 0, 2, 1, 3, 4, 6, 5, 7, 8, 10, 9,
            11, 12, 14, 13, 15,
        )
    } else {
        _mm256_setr_epi8(
            0, 1, 3, 2, 4, 5, 7, 6, 8, 9, 11, 10, 12, 13, 15, 14, 0, 1, 3, 2, 4, 5, 7, 6, 8, 9, 11,
            10, 12, 13, 15, 14,
        )
    };
    let ones = _mm256_set1_epi8(-1);
    let mut any = _mm256_setzero_si256();
    let bytes: &mut [u8] = bytemuck::cast_slice_mut(words);
    // Words `4 q ..= 4 q + 3` read bytes `32 q + AHEAD ..` and write `32 q .. 32 q + 32`: no
    // step reads what an earlier one wrote.
    let quads = n / 4;
    // One bounds check for the loop: every window ends within these bytes.
    let steps = &mut bytes[..32 * quads + AHEAD];
    for q in 0..quads {
        let from = &steps[32 * q + AHEAD..][..32];
        let window: [u8; 32] = core::array::from_fn(|i| from[i]);
        let fixed = _mm256_xor_si256(_mm256_shuffle_epi8(bytemuck::cast(window), swap), ones);
        any = _mm256_or_si256(any, fixed);
        let fixed: [u8; 32] = bytemuck::cast(fixed);
        steps[32 * q..32 * q + 32].copy_from_slice(&fixed);
    }
    let mut any_rest = 0;
    for k in 4 * quads..n {
        let from = &bytes[8 * k + AHEAD..][..8];
        let [b0, b1, b2, b3, b4, b5, b6, b7] = core::array::from_fn(|i| from[i]);
        let in_order = if AHEAD == 0 {
            [b0, b2, b1, b3, b4, b6, b5, b7]
        } else {
            [b0, b1, b3, b2, b4, b5, b7, b6]
        };
        let word = !u64::from_le_bytes(in_order);
        any_rest |= word;
        bytes[8 * k..8 * k + 8].copy_from_slice(&word.to_le_bytes());
    }
    _mm256_testz_si256(any, any) == 0 || any_rest != 0
}

/// The 1,156 rows of 34 bits of an array of edge 34 into `out`, from `flat`, its occupancy
/// in id order 64 ids a word (and an empty word after the last), four rows a step (see the
/// [module docs](self)).
#[cfg(target_feature = "sse2")]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn cut_34_rows(flat: &FlatColumns, out: &mut [u64]) {
    // Dwords 0, 1 for row 0, 1, 2 for row 1, 2, 3 for row 2 and 3, 4 for row 3.
    let dwords = _mm256_setr_epi32(0, 1, 1, 2, 2, 3, 3, 4);
    let shifts = _mm256_setr_epi64x(0, 2, 4, 6);
    let row = _mm256_set1_epi64x((1 << 34) - 1);
    debug_assert_eq!(out.len(), 34 * 34);
    let bytes: &[u8] = bytemuck::cast_slice(&flat[..]);
    let four_rows = |window: &[u8]| -> [u64; 4] {
        let window: [u8; 32] = core::array::from_fn(|i| window[i]);
        let spread = _mm256_permutevar8x32_epi32(bytemuck::cast(window), dwords);
        bytemuck::cast(_mm256_and_si256(_mm256_srlv_epi64(spread, shifts), row))
    };
    // 32 rows (136 bytes) a block, with one bounds check: its eighth window reads 32 bytes
    // from byte 119.
    let (blocks, rest) = out.as_chunks_mut::<32>();
    for (b, block) in blocks.iter_mut().enumerate() {
        let from = &bytes[136 * b..][..151];
        for (g, four) in block.as_chunks_mut::<4>().0.iter_mut().enumerate() {
            *four = four_rows(&from[17 * g..]);
        }
    }
    let first = 136 * blocks.len();
    for (g, four) in rest.as_chunks_mut::<4>().0.iter_mut().enumerate() {
        *four = four_rows(&bytes[first + 17 * g..]);
    }
}

#[cfg(all(test, target_feature = "sse2"))]
mod tests {
    use alloc::vec::Vec;

    use super::*;
    use crate::blocky::plain::build_columns as build_columns_portable;

    /// The kernel and the id-order pass against the portable row mask, on rows of air and ids
    /// at the ends of the 16-bit range, where a signed saturating pack could turn an id into
    /// air, in every position of the lanes. 1 to 9 rows a call, so both the four-row steps and
    /// the rest run; one call in ten is all air, which the pass must report. Only a CPU with
    /// AVX2 runs these kernels, so only one can check them; without AVX2 the test says so on
    /// stderr.
    #[test]
    fn the_kernel_and_the_id_order_pass_give_each_row_s_occupancy() {
        if !crate::instruction_set::x86_v3_or_skip("the x86-64-v3 column kernels") {
            return;
        }
        let values = [
            0u16, 1, 2, 0x7F, 0x80, 0xFF, 0x100, 0x7FFF, 0x8000, 0xFF00, 0xFFFF,
        ];
        let mut rng = voxel_scene::rng::Rng::new(11);
        for call in 0..600 {
            let air = call % 10 == 0;
            let rows: Vec<[u16; 64]> = (0..1 + call % 9)
                .map(|r| {
                    core::array::from_fn(|i| match (air, call, r) {
                        (true, ..) => 0,
                        (_, 1, 0) => values[1 + i % (values.len() - 1)],
                        _ => values[rng.below(values.len() as u64) as usize],
                    })
                })
                .collect();
            let mut words = [!0; 10];
            #[expect(
                unsafe_code,
                reason = "calls the AVX2 kernels on a CPU checked to have them"
            )]
            // SAFETY: `X86V3.is_supported()` found every feature the kernels are compiled for.
            let any = unsafe {
                air_in_lane_order(&rows, &mut words);
                to_id_order_non_air::<0>(&mut words, rows.len())
            };
            for (r, row) in rows.iter().enumerate() {
                assert_eq!(words[r], row_non_air(row), "call {call}, row {r}: {row:?}");
            }
            assert_eq!(words[rows.len()..], [!0; 10][rows.len()..], "call {call}");
            assert_eq!(any, !air, "call {call}");
        }
    }

    /// The columns of arrays at every placement an allocator gives (on a 32-byte boundary,
    /// 16 bytes past one, which reads from the ninth id on, and the odd placements of a
    /// sub-slice) equal the portable builder's, at every padded edge.
    #[test]
    fn columns_are_the_same_at_every_placement_of_the_array() {
        if !crate::instruction_set::x86_v3_or_skip("the x86-64-v3 column kernels") {
            return;
        }
        let mut rng = voxel_scene::rng::Rng::new(23);
        for p in [10, 18, 34, 64] {
            let len = p * p * p;
            let mut buffer: Vec<u16> = alloc::vec![0; len + 32];
            // `buffer[base..]` starts on a 32-byte boundary.
            let base = (0..16)
                .find(|&o| (buffer[o..].as_ptr() as usize).is_multiple_of(32))
                .expect("a u16 buffer has a 32-byte boundary in its first 16 ids");
            for skew in [0, 8, 1, 4, 15] {
                let at = base + skew;
                // All air; a solid first id; solid ids at the end and at the eighth and
                // ninth, where the skewed read starts; random ids.
                for fill in 0..4 {
                    for (i, v) in buffer[at..at + len].iter_mut().enumerate() {
                        *v = match fill {
                            0 => 0,
                            1 => u16::from(i == 0),
                            2 => u16::from(i == len - 1 || i == 7 || i == 8),
                            _ => match rng.below(4) {
                                0 | 1 => 0,
                                2 => 0x8000,
                                _ => rng.below(65_535) as u16 + 1,
                            },
                        };
                    }
                    let voxels = &buffer[at..at + len];
                    assert_eq!(starts_at_16_of_32(voxels), skew == 8);
                    let (mut want, mut want_flat) = (
                        Words::default(),
                        alloc::boxed::Box::new(FlatColumns([0; FLAT_WORDS])),
                    );
                    let want_any = build_columns_portable(p, voxels, &mut want, &mut want_flat);
                    let mut got = Words::default();
                    got.sized(3).fill(5);
                    let mut flat = alloc::boxed::Box::new(FlatColumns([!0; FLAT_WORDS]));
                    #[expect(
                        unsafe_code,
                        reason = "calls the AVX2 builder on a CPU checked to have it"
                    )]
                    // SAFETY: `X86V3.is_supported()` found every feature it is compiled for.
                    let any = unsafe { build_columns_x86_v3(p, voxels, &mut got, &mut flat) };
                    assert_eq!(any, want_any, "edge {p}, skew {skew}, fill {fill}");
                    if any {
                        assert_eq!(*got, *want, "edge {p}, skew {skew}, fill {fill}");
                    }
                }
            }
        }
    }
}
