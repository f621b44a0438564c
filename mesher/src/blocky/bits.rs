//! Bit tools for 64-voxel rows: occupancy and id-match masks of a row of `u16` ids, the
//! 64 x 64 bit-matrix transpose that turns x-rows into y-rows, the iterator over a word's set
//! bits ([`ones`]), and indexes kept in range by a mask ([`masked`]).

/// Gathers 8 bytes of `0` / `1` (byte `i` the value of bit `i`) into the low 8 bits.
///
/// The multiplier has bit `56 - 7k` set for `k = 0..8`, so byte `i` (bit `8i`) lands on bit
/// `56 + 8i - 7k`: for `k = i` that is bit `56 + i` of the top byte. All 64 partial products
/// land on distinct bits (`8i - 7k` is unique per pair), and every other one lands below bit
/// 56 or past bit 63, so nothing carries into the top byte.
#[inline(always)]
fn gather8(bytes: [u8; 8]) -> u64 {
    (u64::from_le_bytes(bytes).wrapping_mul(0x0102_0408_1020_4080)) >> 56
}

/// Bit `i` set iff `row[i] == id`, for a row of `N` ids (48 or 64), with SSE2: compares of 8
/// ids at a time, packed to bytes, 16 mask bits per `pmovmskb` (31 instructions for 64 ids).
/// Compilers do not find `pmovmskb` in portable code, and the portable [`row_mask`] compiles
/// badly for AVX2 (its byte gathers become emulated 64-bit vector multiplies).
#[cfg(target_feature = "sse2")]
#[inline(always)]
fn row_equal_64<const N: usize>(row: &[u16; N], id: u16) -> u64 {
    use safe_arch::{
        cmp_eq_mask_i16_m128i, m128i, move_mask_i8_m128i, pack_i16_to_i8_m128i, set_splat_i16_m128i,
    };
    debug_assert!(N <= 64 && N.is_multiple_of(16));
    let want = set_splat_i16_m128i(id as i16);
    let mut mask = 0u64;
    for (k, sixteen) in row.chunks_exact(16).enumerate() {
        let low: [u16; 8] = core::array::from_fn(|j| sixteen[j]);
        let high: [u16; 8] = core::array::from_fn(|j| sixteen[8 + j]);
        let bytes = pack_i16_to_i8_m128i(
            cmp_eq_mask_i16_m128i(m128i::from(low), want),
            cmp_eq_mask_i16_m128i(m128i::from(high), want),
        );
        mask |= u64::from(move_mask_i8_m128i(bytes) as u16) << ((16 * k) & 63);
    }
    mask
}

/// Bit `i` set iff `a[i] == b[i]`, for two rows of 64 ids: [`row_equal_64`]'s compares and
/// packing, against a second row instead of one id.
#[cfg(target_feature = "sse2")]
#[inline(always)]
fn rows_equal_64(a: &[u16; 64], b: &[u16; 64]) -> u64 {
    use safe_arch::{cmp_eq_mask_i16_m128i, m128i, move_mask_i8_m128i, pack_i16_to_i8_m128i};
    let mut mask = 0u64;
    for (k, (a, b)) in a.chunks_exact(16).zip(b.chunks_exact(16)).enumerate() {
        let half = |row: &[u16], from: usize| {
            m128i::from(core::array::from_fn::<u16, 8, _>(|j| row[from + j]))
        };
        let bytes = pack_i16_to_i8_m128i(
            cmp_eq_mask_i16_m128i(half(a, 0), half(b, 0)),
            cmp_eq_mask_i16_m128i(half(a, 8), half(b, 8)),
        );
        mask |= u64::from(move_mask_i8_m128i(bytes) as u16) << ((16 * k) & 63);
    }
    mask
}

/// Bit `i` set iff `a[i] == b[i]`, for two rows of 64 ids.
#[inline(always)]
pub(crate) fn rows_equal(a: &[u16; 64], b: &[u16; 64]) -> u64 {
    #[cfg(target_feature = "sse2")]
    return rows_equal_64(a, b);
    #[cfg(not(target_feature = "sse2"))]
    (0..64).fold(0u64, |mask, i| mask | u64::from(a[i] == b[i]) << i)
}

/// Bit `i` (`i < N`) set iff `a[i] == b[i]`: two runs of `N` ids compared (`N` a multiple of
/// 16, at most 64); with SSE2 two compares of 8 ids packed to bytes, one `pmovmskb` per 16.
#[inline(always)]
pub(crate) fn runs_equal<const N: usize>(a: &[u16; N], b: &[u16; N]) -> u64 {
    #[cfg(target_feature = "sse2")]
    {
        use safe_arch::{
            cmp_eq_mask_i16_m128i, load_unaligned_m128i, move_mask_i8_m128i, pack_i16_to_i8_m128i,
        };
        debug_assert!(N <= 64 && N.is_multiple_of(16));
        let a: &[[u8; 16]] = bytemuck::cast_slice(a);
        let b: &[[u8; 16]] = bytemuck::cast_slice(b);
        let mut mask = 0u64;
        for k in 0..N / 16 {
            let eq = |j: usize| {
                cmp_eq_mask_i16_m128i(load_unaligned_m128i(&a[j]), load_unaligned_m128i(&b[j]))
            };
            let bytes = pack_i16_to_i8_m128i(eq(2 * k), eq(2 * k + 1));
            mask |= u64::from(move_mask_i8_m128i(bytes) as u16) << ((16 * k) & 63);
        }
        mask
    }
    #[cfg(not(target_feature = "sse2"))]
    (0..N).fold(0u64, |mask, i| mask | u64::from(a[i] == b[i]) << i)
}

/// Bit `i` (`i < N`) set iff `run[i] > last`; with SSE2 one saturating subtraction per 8 ids
/// (not zero iff the id is above `last`).
#[inline(always)]
pub(crate) fn runs_reach<const N: usize>(run: &[u16; N], last: u16) -> u64 {
    #[cfg(target_feature = "sse2")]
    {
        use safe_arch::{
            cmp_eq_mask_i16_m128i, load_unaligned_m128i, m128i, move_mask_i8_m128i,
            pack_i16_to_i8_m128i, set_splat_i16_m128i, sub_saturating_u16_m128i,
        };
        let run: &[[u8; 16]] = bytemuck::cast_slice(run);
        let last = set_splat_i16_m128i(last as i16);
        let zero = m128i::default();
        let mut within = 0u64;
        for k in 0..N / 16 {
            let under = |j: usize| {
                let excess = sub_saturating_u16_m128i(load_unaligned_m128i(&run[j]), last);
                cmp_eq_mask_i16_m128i(excess, zero)
            };
            let bytes = pack_i16_to_i8_m128i(under(2 * k), under(2 * k + 1));
            within |= u64::from(move_mask_i8_m128i(bytes) as u16) << ((16 * k) & 63);
        }
        !within & (u64::MAX >> (64 - N))
    }
    #[cfg(not(target_feature = "sse2"))]
    (0..N).fold(0u64, |mask, i| mask | u64::from(run[i] > last) << i)
}

/// Bit `i` set iff `pred(row[i])`, for rows of at most 64 ids.
///
/// A full row of 64 is turned into 64 bytes of `0` / `1` first (one vectorised compare over the
/// whole row), then packed 8 bytes at a time with [`gather8`]: comparing and packing group by
/// group is what the compiler does not vectorise well.
#[inline(always)]
fn row_mask(row: &[u16], pred: impl Fn(u16) -> bool) -> u64 {
    if let Ok(full) = <&[u16; 64]>::try_from(row) {
        let bytes: [u8; 64] = core::array::from_fn(|j| u8::from(pred(full[j])));
        let mut mask = 0u64;
        for (i, group) in bytes.chunks_exact(8).enumerate() {
            let group: [u8; 8] = core::array::from_fn(|j| group[j]);
            mask |= gather8(group) << ((8 * i) & 63);
        }
        return mask;
    }
    let mut mask = 0u64;
    let groups = row.chunks_exact(8);
    let tail = groups.remainder();
    let mut shift = 0;
    for group in groups {
        let bytes: [u8; 8] = core::array::from_fn(|j| u8::from(pred(group[j])));
        mask |= gather8(bytes) << (shift & 63);
        shift += 8;
    }
    for &v in tail {
        mask |= u64::from(pred(v)) << (shift & 63);
        shift += 1;
    }
    mask
}

/// Bit `l` set iff `lines[l]` is not zero: the lines of a slice that hold a face.
///
/// Written as one flag per line shifted into place: the compiler turns the whole loop into
/// 16 vector compares with zero, each ANDed with the constant bits `1 << l` of its 4 lines,
/// and an OR of them: far fewer instructions than 64 bytes of `0` / `1` and 8 byte gathers.
#[inline(always)]
pub(crate) fn nonzero_lines(lines: &[u64; 64]) -> u64 {
    let mut mask = 0u64;
    for (l, &line) in lines.iter().enumerate() {
        mask |= u64::from(line != 0) << l;
    }
    mask
}

/// Occupancy of a row: bit `i` set iff `row[i]` is not air (`0`). `row.len() <= 64`.
#[inline(always)]
pub(crate) fn row_non_air(row: &[u16]) -> u64 {
    #[cfg(target_feature = "sse2")]
    if let Ok(full) = <&[u16; 64]>::try_from(row) {
        return !row_equal_64(full, 0);
    }
    row_mask(row, |v| v != 0)
}

/// Bit `i` set iff `row[i] == id`. `row.len() <= 64`.
#[inline(always)]
pub(crate) fn row_equal(row: &[u16], id: u16) -> u64 {
    #[cfg(target_feature = "sse2")]
    if let Ok(full) = <&[u16; 64]>::try_from(row) {
        return row_equal_64(full, id);
    }
    row_mask(row, |v| v == id)
}

/// The faces of `faces` whose id in `row` is `id`, for a row of ids whose faces include one
/// of `id`: usually every face of a line has one id, so a test that the row holds no other
/// solid id (a compare-and-OR, like [`row_contains`]) answers without the bit packing of
/// [`row_equal`].
///
/// Rows of 64, 48 (three 16-id registers, enough for a 32^3 chunk's rows of 34) and 32 ids
/// (half a row of 64) are compared as arrays; other lengths take a loop.
#[inline(always)]
pub(crate) fn faces_of_id(row: &[u16], id: u16, faces: u64) -> u64 {
    // A row as an array: the fold is unrolled, with no loop over a run-time length.
    if let Ok(full) = <&[u16; 64]>::try_from(row) {
        return faces_of_id_in(full, id, faces);
    }
    if let Ok(short) = <&[u16; 48]>::try_from(row) {
        return faces_of_id_in(short, id, faces);
    }
    if let Ok(half) = <&[u16; 32]>::try_from(row) {
        return faces_of_id_in(half, id, faces);
    }
    if !holds_other_solid(row, id) {
        return faces;
    }
    faces & row_equal(row, id)
}

/// True if `row` holds a solid id other than `id`: a compare-and-OR, like [`row_contains`].
#[inline(always)]
fn holds_other_solid(row: &[u16], id: u16) -> bool {
    row.iter()
        .fold(0u16, |acc, &v| acc | u16::from(v != 0 && v != id))
        != 0
}

/// [`faces_of_id`] on a row of `N` ids (48 or 64).
#[inline(always)]
fn faces_of_id_in<const N: usize>(row: &[u16; N], id: u16, faces: u64) -> u64 {
    if !holds_other_solid(row, id) {
        return faces;
    }
    #[cfg(target_feature = "sse2")]
    let equal = row_equal_64(row, id);
    #[cfg(not(target_feature = "sse2"))]
    let equal = row_mask(row, |v| v == id);
    faces & equal
}

/// The rows of a slab from its first row with a set bit to its last (indexes into `rows`, a
/// slab's occupancy rows), or `None` if every row is empty: the only rows of the slab whose
/// ids need reading when looking for ids that are not air.
#[inline(always)]
pub(crate) fn occupied_rows(rows: &[u64]) -> Option<core::ops::Range<usize>> {
    match (
        rows.iter().position(|&c| c != 0),
        rows.iter().rposition(|&c| c != 0),
    ) {
        (Some(first), Some(last)) => Some(first..last + 1),
        _ => None,
    }
}

/// True if `row` holds `id` anywhere: a compare-and-OR over the row that vectorises without
/// any bit packing, much cheaper than [`row_equal`] when (as usual) the answer is no.
#[inline(always)]
pub(crate) fn row_contains(row: &[u16], id: u16) -> bool {
    row.iter().fold(0u16, |acc, &v| acc | u16::from(v == id)) != 0
}

/// `i` as an index into an array of `N` entries (`N` a power of two): `i & (N - 1)`, with
/// `i < N` asserted in debug builds.
///
/// For indexes that are in range by an invariant the compiler cannot see (the line after or
/// before a line, `l + 1` and `l - 1`; rows of a run-time chunk size; the end of a slice's
/// quad buffer): a plain index would add a compare and a branch to a panic in the hot loops,
/// while the mask is one AND. Tests and fuzzers run debug builds, so a broken invariant panics
/// there rather than giving wrong quads.
#[inline(always)]
pub(crate) fn masked<const N: usize>(i: usize) -> usize {
    debug_assert!(
        N.is_power_of_two() && i < N,
        "index {i} out of range 0..{N}"
    );
    i & (N - 1)
}

/// The indexes of the set bits of `bits`, lowest first: the bit-scan loop (`trailing_zeros`,
/// then clear the lowest set bit) written once. Every index is below 64.
#[inline(always)]
pub(crate) fn ones(bits: u64) -> Ones {
    Ones(bits)
}

/// The iterator of [`ones`]: the bits not yielded yet.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ones(u64);

impl Ones {
    /// The index the next call to `next` yields, without taking it.
    #[inline(always)]
    pub(crate) fn peek(self) -> Option<usize> {
        (self.0 != 0).then(|| self.0.trailing_zeros() as usize)
    }
}

impl Iterator for Ones {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let i = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(i)
    }
}

/// The voxels of row `row` all of whose 6 neighbours are solid, so that they show no face:
/// `before` and `after` are the rows on either side in the same slab, `under` and `over` the
/// same row in the slabs on either side (one bit a voxel, x along the bits).
#[inline(always)]
pub(crate) fn buried(row: u64, [before, after]: [u64; 2], [under, over]: [u64; 2]) -> u64 {
    (row >> 1) & (row << 1) & before & after & under & over
}

/// True if `bits` has at least 4 set bits (without `popcnt`, which the baseline x86-64 target
/// lacks): the lines worth the fast path's fixed cost.
#[inline(always)]
pub(crate) fn many(bits: u64) -> bool {
    let mut x = bits & bits.wrapping_sub(1);
    x &= x.wrapping_sub(1);
    x &= x.wrapping_sub(1);
    x != 0
}

/// Transposes an 8 x 8 bit matrix held in one word, a row a byte: afterwards bit `c` of byte
/// `r` is what bit `r` of byte `c` was. Three rounds of block swaps (1, 2 and 4 bits), each
/// one masked exchange within the word.
#[inline(always)]
pub(crate) fn transpose8(mut m: u64) -> u64 {
    let t = (m ^ (m >> 7)) & 0x00AA_00AA_00AA_00AA;
    m ^= t ^ (t << 7);
    let t = (m ^ (m >> 14)) & 0x0000_CCCC_0000_CCCC;
    m ^= t ^ (t << 14);
    let t = (m ^ (m >> 28)) & 0x0000_0000_F0F0_F0F0;
    m ^ t ^ (t << 28)
}

/// Transposes a 64 x 64 bit matrix in place: afterwards bit `c` of word `r` is what bit `r` of
/// word `c` was. Six rounds of block swaps (32, 16, ..., 1), each a masked exchange between
/// word pairs, so the cost is fixed (about 1,200 simple operations) whatever the bits are.
#[inline(always)]
pub(crate) fn transpose64(m: &mut [u64; 64]) {
    let mut width = 32usize;
    let mut mask: u64 = 0x0000_0000_FFFF_FFFF;
    while width != 0 {
        // Blocks of 2 * width words: the low `width` words swap their high bit-blocks with the
        // low bit-blocks of the high `width` words.
        for block in m.chunks_exact_mut(2 * width) {
            let (lo, hi) = block.split_at_mut(width);
            for (a, b) in lo.iter_mut().zip(hi.iter_mut()) {
                let t = ((*a >> width) ^ *b) & mask;
                *b ^= t;
                *a ^= t << width;
            }
        }
        width >>= 1;
        mask ^= mask << width;
    }
}

/// [`transpose64`] of a matrix whose words from `rows` on are zero, with AVX2, for the
/// x86-64-v3 copy of the mesher (the portable one calls [`transpose64`]). Up to 34 rows (the
/// padded slices of 32^3 chunks, and two 32 x 32 windows side by side) it takes about half
/// of [`transpose64`]'s operations (see [`transpose_34_rows_x86_v3`]); more rows take
/// [`transpose64`], compiled here with AVX2.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
pub(crate) fn transpose_rows_x86_v3(m: &mut [u64; 64], rows: usize) {
    if rows <= 34 {
        transpose_34_rows_x86_v3(m);
    } else {
        transpose64(m);
    }
}

/// [`transpose_rows_x86_v3`] on an x86-64 target without SSE (soft float, as
/// `x86_64-unknown-none`), which cannot hold AVX2 vectors: [`transpose64`].
#[cfg(all(target_arch = "x86_64", not(target_feature = "sse2")))]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
pub(crate) fn transpose_rows_x86_v3(m: &mut [u64; 64], _rows: usize) {
    transpose64(m);
}

/// [`transpose64`] of a matrix whose words from 34 on are zero, in AVX2 registers of four
/// words.
///
/// Words 0 to 31 take the last five rounds of [`transpose64`] only (8 registers instead of
/// 16, and no first round): that transposes their low 32 bits and their high 32 bits as two
/// 32 x 32 matrices side by side, the first as words 0 to 31 of the result and the second,
/// shifted down, as words 32 to 63. Words 32 and 33 then become bits 32 and 33 of every
/// word: bit `x` of word 32 is bit 32 of word `x`. That is half the registers and one round
/// less than [`transpose64`] of the whole matrix.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn transpose_34_rows_x86_v3(m: &mut [u64; 64]) {
    use core::arch::x86_64::{
        __m256i, _mm256_and_si256, _mm256_or_si256, _mm256_permute2x128_si256, _mm256_set1_epi64x,
        _mm256_setr_epi64x, _mm256_slli_epi64, _mm256_srli_epi64, _mm256_srlv_epi64,
        _mm256_unpackhi_epi64, _mm256_unpacklo_epi64, _mm256_xor_si256,
    };
    debug_assert!(m[34..].iter().all(|&word| word == 0));
    let (word32, word33) = (m[32], m[33]);
    let quads = m.as_chunks_mut::<4>().0;
    let mut r: [__m256i; 8] = core::array::from_fn(|i| bytemuck::cast(quads[i % quads.len()]));
    // Between registers: words `i` and `i + W` of a block of `2 W` are in registers `k` and
    // `k + W / 4`.
    macro_rules! across {
        ($w:literal, $step:literal, $firsts:expr, $mask:literal) => {{
            let mask = _mm256_set1_epi64x($mask);
            for k in $firsts {
                let (a, b) = (r[k], r[k + $step]);
                let t = _mm256_and_si256(_mm256_xor_si256(_mm256_srli_epi64::<$w>(a), b), mask);
                r[k + $step] = _mm256_xor_si256(b, t);
                r[k] = _mm256_xor_si256(a, _mm256_slli_epi64::<$w>(t));
            }
        }};
    }
    across!(16, 4, [0, 1, 2, 3], 0x0000_FFFF_0000_FFFF);
    across!(8, 2, [0, 1, 4, 5], 0x00FF_00FF_00FF_00FF);
    across!(4, 1, [0, 2, 4, 6], 0x0F0F_0F0F_0F0F_0F0F);
    // Within registers, two at a time: the pairs gathered lane by lane into `lo` and `hi`
    // (words 0, 1 with 2, 3 for width 2; 0 with 1 and 2 with 3 for width 1), swapped, and put
    // back.
    macro_rules! within {
        ($lo:expr, $hi:expr, $w:literal, $mask:literal) => {{
            let (lo, hi) = ($lo, $hi);
            let mask = _mm256_set1_epi64x($mask);
            let t = _mm256_and_si256(_mm256_xor_si256(_mm256_srli_epi64::<$w>(lo), hi), mask);
            (
                _mm256_xor_si256(lo, _mm256_slli_epi64::<$w>(t)),
                _mm256_xor_si256(hi, t),
            )
        }};
    }
    for k in [0, 2, 4, 6] {
        let (a, b) = (r[k], r[k + 1]);
        let (lo, hi) = within!(
            _mm256_permute2x128_si256::<0x20>(a, b),
            _mm256_permute2x128_si256::<0x31>(a, b),
            2,
            0x3333_3333_3333_3333
        );
        let (a, b) = (
            _mm256_permute2x128_si256::<0x20>(lo, hi),
            _mm256_permute2x128_si256::<0x31>(lo, hi),
        );
        let (lo, hi) = within!(
            _mm256_unpacklo_epi64(a, b),
            _mm256_unpackhi_epi64(a, b),
            1,
            0x5555_5555_5555_5555
        );
        r[k] = _mm256_unpacklo_epi64(lo, hi);
        r[k + 1] = _mm256_unpackhi_epi64(lo, hi);
    }
    let low = _mm256_set1_epi64x(0xFFFF_FFFF);
    // Bit 32 of word x is bit x of word 32: word 32 moved up by 32 and down by x leaves it
    // there; bit 33 comes from word 33 the same way, then up by one. `half` 32 takes the
    // words' high halves, for words x + 32. Four words a register, `shift` their x.
    let bit32 = _mm256_set1_epi64x(1 << 32);
    let extra = |half: u32, shift: __m256i| {
        let from = |word: u64| _mm256_set1_epi64x(((word >> half) << 32) as i64);
        _mm256_or_si256(
            _mm256_and_si256(_mm256_srlv_epi64(from(word32), shift), bit32),
            _mm256_slli_epi64::<1>(_mm256_and_si256(
                _mm256_srlv_epi64(from(word33), shift),
                bit32,
            )),
        )
    };
    let (first, second) = quads.split_at_mut(8);
    // Words 32 and 33 are zero for two 32 x 32 windows, and have no bits from 34 on in a
    // padded slice: those skip the work for them.
    let (any, above) = (word32 | word33 != 0, (word32 | word33) >> 32 != 0);
    for (k, ((quad, high), &corner)) in first.iter_mut().zip(second).zip(&r).enumerate() {
        let x = 4 * k as i64;
        let shift = _mm256_setr_epi64x(x, x + 1, x + 2, x + 3);
        let mut low_words = _mm256_and_si256(corner, low);
        let mut high_words = _mm256_srli_epi64::<32>(corner);
        if any {
            low_words = _mm256_or_si256(low_words, extra(0, shift));
        }
        if above {
            high_words = _mm256_or_si256(high_words, extra(32, shift));
        }
        *quad = bytemuck::cast(low_words);
        *high = bytemuck::cast(high_words);
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec::Vec;

    use super::*;

    #[test]
    fn ones_yields_the_set_bits_lowest_first() {
        for bits in [0u64, 1, 1 << 63, 0x8000_0000_0000_0001, 0x5555, u64::MAX] {
            let want: Vec<usize> = (0..64).filter(|&i| bits >> i & 1 == 1).collect();
            assert_eq!(ones(bits).collect::<Vec<_>>(), want, "{bits:#x}");
            assert_eq!(ones(bits).peek(), want.first().copied());
        }
    }

    #[test]
    fn transpose_matches_the_definition() {
        let mut state = 0x1234_5678_9ABC_DEF1u64;
        let mut m = [0u64; 64];
        for w in m.iter_mut() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            *w = state;
        }
        let original = m;
        transpose64(&mut m);
        for (r, &row) in m.iter().enumerate() {
            for (c, &col) in original.iter().enumerate() {
                assert_eq!((row >> c) & 1, (col >> r) & 1, "bit ({r}, {c})");
            }
        }
    }

    #[test]
    fn transpose8_matches_the_definition() {
        let mut state = 0x0123_4567_89AB_CDEFu64;
        for round in 0..200 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let m = match round {
                0 => 0,
                1 => u64::MAX,
                2 => 1,
                3 => 1 << 63,
                _ => state,
            };
            let t = transpose8(m);
            for r in 0..8 {
                for c in 0..8 {
                    let bit = |w: u64, row: usize, col: usize| (w >> (8 * row + col)) & 1;
                    assert_eq!(bit(t, r, c), bit(m, c, r), "{m:#x} ({r}, {c})");
                }
            }
        }
    }

    /// The x86-64-v3 transpose of matrices with 1 to 64 non-zero words (random bits across
    /// the whole word, full and empty words among them) against [`transpose64`].
    #[test]
    fn the_x86_v3_transpose_matches_transpose64() {
        #[cfg(target_arch = "x86_64")]
        if crate::instruction_set::x86_v3_or_skip("transpose_rows_x86_v3") {
            let mut state = 0x0F1E_2D3C_4B5A_6978u64;
            for rows in [1, 2, 17, 32, 33, 34, 35, 64] {
                for round in 0..20 {
                    let mut m = [0u64; 64];
                    for word in m.iter_mut().take(rows) {
                        state ^= state << 13;
                        state ^= state >> 7;
                        state ^= state << 17;
                        *word = match (round % 4, state % 5) {
                            (0, 0) => u64::MAX,
                            (1, 0) => 0,
                            (2, _) => state & 0x3_FFFF_FFFF,
                            _ => state,
                        };
                    }
                    let mut want = m;
                    transpose64(&mut want);
                    #[expect(
                        unsafe_code,
                        reason = "calls the AVX2 transpose on a CPU checked to have it"
                    )]
                    // SAFETY: `X86V3.is_supported()` found every feature it is compiled for.
                    unsafe {
                        transpose_rows_x86_v3(&mut m, rows);
                    }
                    assert_eq!(m, want, "{rows} rows, round {round}");
                }
            }
        }
    }

    #[test]
    fn nonzero_lines_match_a_plain_loop() {
        let lines: [u64; 64] = core::array::from_fn(|l| if l % 3 == 0 { 0 } else { 1 << (l % 64) });
        let want = (0..64).fold(0u64, |m, l| m | u64::from(lines[l] != 0) << l);
        assert_eq!(nonzero_lines(&lines), want);
        assert_eq!(nonzero_lines(&[0; 64]), 0);
        assert_eq!(nonzero_lines(&[u64::MAX; 64]), u64::MAX);
    }

    /// Both answers of `faces_of_id`: a row of one solid id and air (the faces come back
    /// whole), and rows with a second id anywhere, at a face or not (only the faces of the id).
    #[test]
    fn faces_of_id_keeps_exactly_the_faces_of_the_id() {
        // Rows of 32, 48 and 64 are compared as arrays, others (34) in a loop.
        for len in [32usize, 34, 48, 64] {
            let faces = 0x5555_5555_5555_5555u64 >> (64 - len) & !1;
            let one_id: [u16; 64] = core::array::from_fn(|i| if i % 2 == 0 { 9 } else { 0 });
            assert_eq!(faces_of_id(&one_id[..len], 9, faces), faces);
            for other_at in [2, 3, len - 1] {
                let mut mixed = one_id;
                mixed[other_at] = 65535;
                let want = (0..len).fold(0u64, |m, i| m | u64::from(mixed[i] == 9) << i);
                assert_eq!(
                    faces_of_id(&mixed[..len], 9, faces),
                    faces & want,
                    "len {len}"
                );
            }
        }
    }

    #[test]
    fn row_masks_match_a_plain_loop() {
        for len in [10usize, 18, 34, 64] {
            let row: [u16; 64] = core::array::from_fn(|i| ((i * 7 + len) % 5) as u16);
            let row = &row[..len];
            let mut non_air = 0u64;
            let mut threes = 0u64;
            for (i, &v) in row.iter().enumerate() {
                non_air |= u64::from(v != 0) << i;
                threes |= u64::from(v == 3) << i;
            }
            assert_eq!(row_non_air(row), non_air, "len {len}");
            assert_eq!(row_equal(row, 3), threes, "len {len}");
        }
    }

    /// Ids at the ends of the 16-bit range, where a signed compare or a saturating pack could
    /// go wrong (the SSE2 path compares and packs signed lanes).
    #[test]
    fn row_masks_hold_at_the_ends_of_the_id_range() {
        let values = [0u16, 1, 0x7FFF, 0x8000, 0x8001, 0xFFFE, 0xFFFF];
        for len in [10usize, 64] {
            let row: [u16; 64] = core::array::from_fn(|i| values[(i * 3) % values.len()]);
            let row = &row[..len];
            for id in values {
                let want = row
                    .iter()
                    .enumerate()
                    .fold(0u64, |m, (i, &v)| m | u64::from(v == id) << i);
                assert_eq!(row_equal(row, id), want, "len {len} id {id:#x}");
            }
            let non_air = row
                .iter()
                .enumerate()
                .fold(0u64, |m, (i, &v)| m | u64::from(v != 0) << i);
            assert_eq!(row_non_air(row), non_air, "len {len}");
        }
    }

    /// Rows equal, different, and equal at some lanes, with ids at the ends of the range.
    #[test]
    fn rows_equal_matches_a_plain_loop() {
        let values = [0u16, 1, 9, 0x7FFF, 0x8000, 0xFFFF];
        let a: [u16; 64] = core::array::from_fn(|i| values[(i * 5) % values.len()]);
        for shift in 0..values.len() {
            let b: [u16; 64] =
                core::array::from_fn(|i| values[(i * 5 + shift * (i % 3)) % values.len()]);
            let want = (0..64).fold(0u64, |m, i| m | u64::from(a[i] == b[i]) << i);
            assert_eq!(rows_equal(&a, &b), want, "shift {shift}");
        }
        assert_eq!(rows_equal(&a, &a), u64::MAX);
    }
}
