//! Fixed-width unsigned fields packed into `u64` words, plus the SWAR helpers that turn a run of
//! fields into a one-bit-per-field mask.
//!
//! Field `i` of a `bits`-wide array lives in word `i / (64 / bits)` at bit
//! `(i % (64 / bits)) * bits`. `bits` divides 64 (1, 2, 4, 8 or 16), so no field straddles two
//! words, and the words written out little-endian are exactly the little-endian bit stream the
//! chunk codec stores. Fields past the logical length (the tail of the last word) are kept zero.
//!
//! Callers pass indices they have already checked against the length; this module indexes its
//! words directly.

use alloc::vec;
use alloc::vec::Vec;

/// The low `n` bits set (`n` up to 64).
#[inline]
pub(crate) const fn low_bits(n: usize) -> u64 {
    if n >= 64 { u64::MAX } else { (1u64 << n) - 1 }
}

/// A word with a 1 in the lowest bit of every `bits`-wide field.
#[inline]
const fn field_lsbs(bits: u32) -> u64 {
    let mut pattern = 0u64;
    let mut shift = 0;
    while shift < 64 {
        pattern |= 1 << shift;
        shift += bits;
    }
    pattern
}

/// `(shift, mask)` steps that gather bits sitting at multiples of `bits` into the low
/// `64 / bits` bits (a portable `pext`). Each step merges pairs of neighbouring groups.
const fn compaction_steps(bits: u32) -> [(u32, u64); 6] {
    let mut steps = [(0u32, u64::MAX); 6];
    let mut block = bits;
    let mut group = 1u32;
    let mut n = 0;
    while block < 64 && group < block {
        let new_block = block * 2;
        let new_group = group * 2;
        let mask = if new_block >= 64 {
            low_bits(new_group as usize)
        } else {
            low_bits(new_group as usize) * field_lsbs(new_block)
        };
        steps[n] = (block - group, mask);
        n += 1;
        block = new_block;
        group = new_group;
    }
    steps
}

/// For one word of `B`-bit fields: bit `k` of the result is set iff field `k` differs from
/// `key`. The result has `64 / B` meaningful low bits.
#[inline(always)]
fn fields_not_equal_w<const B: u32>(word: u64, key: u64) -> u64 {
    let lsbs = const { field_lsbs(B) };
    let v = word ^ (key * lsbs);
    if B == 1 {
        return v;
    }
    let high = lsbs << (B - 1);
    let low = !high;
    // High bit of each field set iff the field is non-zero; adding `low` cannot carry out of a
    // field because the addend's high bit is clear.
    let mut x = ((((v & low) + low) | v) & high) >> (B - 1);
    for (shift, mask) in const { compaction_steps(B) } {
        x = (x | (x >> shift)) & mask;
    }
    x
}

/// [`fields_not_equal_w`] for a width known only at run time.
#[cfg(test)]
fn fields_not_equal(word: u64, bits: u32, key: u64) -> u64 {
    match bits {
        1 => fields_not_equal_w::<1>(word, key),
        2 => fields_not_equal_w::<2>(word, key),
        4 => fields_not_equal_w::<4>(word, key),
        8 => fields_not_equal_w::<8>(word, key),
        _ => fields_not_equal_w::<16>(word, key),
    }
}

/// Fields `start..start + out.len()` of `words` at width `B`, mapped through `f` into `out`.
#[inline(always)]
fn decode_run_w<const B: u32, T>(
    words: &[u64],
    start: usize,
    out: &mut [T],
    mut f: impl FnMut(u32) -> T,
) {
    let per = 64 / B as usize;
    let mask = low_bits(B as usize);
    let mut w = start / per;
    let mut done = 0;
    let skip = start % per;
    if skip != 0 {
        let mut word = words[w] >> (skip as u32 * B);
        let take = (per - skip).min(out.len());
        for slot in &mut out[..take] {
            *slot = f((word & mask) as u32);
            word >>= B;
        }
        done = take;
        w += 1;
    }
    let rest = &mut out[done..];
    let mut groups = rest.chunks_exact_mut(per);
    for (group, &word) in (&mut groups).zip(&words[w..]) {
        let mut word = word;
        for slot in group {
            *slot = f((word & mask) as u32);
            word >>= B;
        }
        w += 1;
    }
    let tail = groups.into_remainder();
    if !tail.is_empty() {
        let mut word = words[w];
        for slot in tail {
            *slot = f((word & mask) as u32);
            word >>= B;
        }
    }
}

/// Bit `x` set iff field `start + x` of `words` at width `B` differs from `key`, `x < len`.
#[inline(always)]
fn run_not_equal_w<const B: u32>(words: &[u64], start: usize, len: usize, key: u32) -> u64 {
    if len == 0 {
        return 0;
    }
    let per = 64 / B as usize;
    let first = start / per;
    let last = (start + len - 1) / per;
    let skip = start % per;
    // The first word contributes from bit `skip` on; every later word lands `per` bits further.
    let mut mask = fields_not_equal_w::<B>(words[first], u64::from(key)) >> skip;
    let mut at = per - skip;
    for &word in &words[first + 1..=last] {
        mask |= fields_not_equal_w::<B>(word, u64::from(key)) << at;
        at += per;
    }
    mask & low_bits(len)
}

/// `len` fields of `bits` bits each.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct PackedBits {
    bits: u32,
    words: Vec<u64>,
}

impl PackedBits {
    /// Fields per word.
    #[inline]
    pub(crate) const fn per_word(bits: u32) -> usize {
        64 / bits as usize
    }

    /// Words needed for `len` fields.
    #[inline]
    pub(crate) const fn word_count(len: usize, bits: u32) -> usize {
        len.div_ceil(Self::per_word(bits))
    }

    /// `len` zero fields.
    pub(crate) fn zeroed(len: usize, bits: u32) -> Self {
        PackedBits {
            bits,
            words: vec![0; Self::word_count(len, bits)],
        }
    }

    /// Wraps words already in the packed layout (the caller checked their count and padding).
    pub(crate) fn from_words(bits: u32, words: Vec<u64>) -> Self {
        PackedBits { bits, words }
    }

    /// Field width in bits.
    #[inline]
    pub(crate) fn bits(&self) -> u32 {
        self.bits
    }

    /// The packed words.
    #[inline]
    pub(crate) fn words(&self) -> &[u64] {
        &self.words
    }

    /// Heap bytes held (from the capacity).
    pub(crate) fn heap_bytes(&self) -> usize {
        self.words.capacity() * size_of::<u64>()
    }

    /// Field `i`.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> u32 {
        let (w, shift) = self.locate(i);
        ((self.words[w] >> shift) & low_bits(self.bits as usize)) as u32
    }

    /// Word index and bit offset of field `i` (shifts only: `bits` is a power of two).
    #[inline]
    fn locate(&self, i: usize) -> (usize, u32) {
        let log_bits = self.bits.trailing_zeros();
        let log_per = 6 - log_bits;
        let k = i & ((1 << log_per) - 1);
        (i >> log_per, (k as u32) << log_bits)
    }

    /// Sets field `i` to `value` (`value < 2^bits`).
    #[inline]
    pub(crate) fn set(&mut self, i: usize, value: u32) {
        let (w, shift) = self.locate(i);
        let mask = low_bits(self.bits as usize) << shift;
        let word = &mut self.words[w];
        *word = (*word & !mask) | ((u64::from(value) << shift) & mask);
    }

    /// The same `len` fields at another width (every value must fit it).
    pub(crate) fn repacked(&self, len: usize, bits: u32) -> PackedBits {
        let mut out = PackedBits::zeroed(len, bits);
        for i in 0..len {
            out.set(i, self.get(i));
        }
        out
    }

    /// Calls `f(field)` for fields `start..start + out.len()` and stores the results in `out`.
    #[inline]
    pub(crate) fn decode_run<T>(&self, start: usize, out: &mut [T], f: impl FnMut(u32) -> T) {
        let words = &self.words[..];
        match self.bits {
            1 => decode_run_w::<1, T>(words, start, out, f),
            2 => decode_run_w::<2, T>(words, start, out, f),
            4 => decode_run_w::<4, T>(words, start, out, f),
            8 => decode_run_w::<8, T>(words, start, out, f),
            _ => decode_run_w::<16, T>(words, start, out, f),
        }
    }

    /// Bit `x` of the result is set iff field `start + x` differs from `key`, for `x < len`
    /// (`len <= 64`).
    #[inline]
    pub(crate) fn run_not_equal(&self, start: usize, len: usize, key: u32) -> u64 {
        let words = &self.words[..];
        match self.bits {
            1 => run_not_equal_w::<1>(words, start, len, key),
            2 => run_not_equal_w::<2>(words, start, len, key),
            4 => run_not_equal_w::<4>(words, start, len, key),
            8 => run_not_equal_w::<8>(words, start, len, key),
            _ => run_not_equal_w::<16>(words, start, len, key),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_not_equal(word: u64, bits: u32, key: u64) -> u64 {
        let per = 64 / bits;
        let mut m = 0;
        for k in 0..per {
            if (word >> (k * bits)) & low_bits(bits as usize) != key {
                m |= 1 << k;
            }
        }
        m
    }

    #[test]
    fn swar_matches_brute_force() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for bits in [1u32, 2, 4, 8, 16] {
            for _ in 0..2000 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                // Sparse words make equal fields likely.
                let word = state & (state >> 3);
                let key = (state >> 40) & low_bits(bits as usize);
                assert_eq!(
                    fields_not_equal(word, bits, key),
                    brute_not_equal(word, bits, key),
                    "bits {bits} word {word:#x} key {key}"
                );
            }
        }
    }

    #[test]
    fn set_get_and_runs() {
        for bits in [1u32, 2, 4, 8, 16] {
            let len = 238;
            let mut p = PackedBits::zeroed(len, bits);
            for i in 0..len {
                p.set(i, (i as u32 * 7 + 3) & low_bits(bits as usize) as u32);
            }
            for i in 0..len {
                assert_eq!(
                    p.get(i),
                    (i as u32 * 7 + 3) & low_bits(bits as usize) as u32
                );
            }
            for start in [0usize, 1, 5, 62, 100, 174] {
                let run = 64.min(len - start);
                let key = 3 & low_bits(bits as usize) as u32;
                let mut expect = 0u64;
                for x in 0..run {
                    if p.get(start + x) != key {
                        expect |= 1 << x;
                    }
                }
                assert_eq!(
                    p.run_not_equal(start, run, key),
                    expect,
                    "bits {bits} start {start}"
                );
                let mut out = vec![0u32; run];
                p.decode_run(start, &mut out, |v| v);
                for (x, v) in out.iter().enumerate() {
                    assert_eq!(*v, p.get(start + x));
                }
            }
            assert_eq!(p.repacked(len, 16).repacked(len, bits), p);
        }
    }
}
