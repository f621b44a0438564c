//! [`Wide`]: the AVX-512 kernels of [`InstructionSet::X86V4`], which write a line of faces
//! that become 1 x 1 quads 8 quads per vector instruction.
//!
//! The scalar loops spend a bit scan, a key and a store per face (5-40 instructions: on a
//! checkerboard or a random fill, where nearly every face is its own quad, they are most of
//! the time). Here a group of 8 bits of a line is one 512-bit register of 8 candidate quads,
//! one per bit, built with a few whole-register operations; `vpcompressq` keeps the quads of
//! the bits that are faces, in bit order, and one unaligned 64-byte store writes them. The
//! next group's store starts where the kept quads end and overwrites the rest, so the output
//! equals the scalar loops' quad for quad. Lines whose quads share id and AO (`push_bits`)
//! compress bit indices instead, 16 per `vpcompressd`, and build 8 quads per store from them.
//!
//! Only this module holds AVX-512 code, and only a [`Wide`] token reaches it: one exists only
//! on a CPU that runs [`InstructionSet::X86V4`]. Targets without SSE2 (soft-float kernels
//! such as `x86_64-unknown-none`) compile no vector code at all, so there is never a token.

use alloc::vec::Vec;

use voxel_core::formats::PackedQuad;

use crate::InstructionSet;

/// Proof that this CPU runs [`InstructionSet::X86V4`]: the only way to call the kernels.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Wide(());

/// One line of faces that become 1 x 1 quads, in the form the kernel reads.
#[cfg_attr(
    not(all(target_arch = "x86_64", target_feature = "sse2")),
    expect(dead_code, reason = "only the AVX-512 kernel reads a line")
)]
pub(crate) struct UnitLine<'a> {
    /// The faces: bit `b` set for a face at bit `b` (bits 1..=62 at most).
    pub bits: u64,
    /// The id of the face at bit `b` at index `b` (only face bits are read).
    pub ids: &'a [u16; 64],
    /// The AO bytes of the line as 8 bit planes (see [`super::ao::ao_planes`]).
    pub ao: [u64; 8],
    /// Both words of the quad at bit 1 with id and AO zero, as `word1 << 32 | word0`.
    pub first: u64,
    /// Bit offset in word 0 of the bit coordinate.
    pub shift: u32,
}

impl Wide {
    /// The token, if `set` is [`InstructionSet::X86V4`] and this CPU runs it.
    pub(crate) fn new(set: InstructionSet) -> Option<Wide> {
        (cfg!(all(target_arch = "x86_64", target_feature = "sse2"))
            && set == InstructionSet::X86V4
            && set.is_supported())
        .then_some(Wide(()))
    }

    /// Appends to `out` a 1 x 1 quad for every set bit `b` of `bits`, whose words are
    /// `base + (b << shift)` as `word1 << 32 | word0`: the bulk path of
    /// [`Quads::push_bits`](super::faces::Quads::push_bits), same quads in the same order.
    /// Returns false, writing nothing, unless `shift` is that of a quad coordinate (0, 6 or
    /// 12: the kernel is compiled for each).
    #[inline(always)]
    pub(crate) fn push_bits(
        self,
        out: &mut Vec<PackedQuad>,
        bits: u64,
        base: u64,
        shift: u32,
    ) -> bool {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        {
            #[expect(
                unsafe_code,
                reason = "calls AVX-512 code; the token proves the CPU runs it"
            )]
            // SAFETY: a `Wide` exists only if `InstructionSet::X86V4.is_supported()`, which
            // checked every feature `push_bits_avx512` is compiled for.
            unsafe {
                match shift {
                    PackedQuad::X_SHIFT => {
                        kernels::push_bits_avx512::<{ PackedQuad::X_SHIFT }>(out, bits, base);
                    }
                    PackedQuad::Y_SHIFT => {
                        kernels::push_bits_avx512::<{ PackedQuad::Y_SHIFT }>(out, bits, base);
                    }
                    PackedQuad::Z_SHIFT => {
                        kernels::push_bits_avx512::<{ PackedQuad::Z_SHIFT }>(out, bits, base);
                    }
                    _ => return false,
                }
            }
            true
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        {
            let _ = (out, bits, base, shift);
            false
        }
    }

    /// Appends to `out` the quads of `line`, in bit order, and returns the mask of the ids
    /// seen ([`SliceFaces::seen_bit`] of every face's id, OR-ed).
    ///
    /// [`SliceFaces::seen_bit`]: super::faces::SliceFaces::seen_bit
    #[inline(always)]
    pub(crate) fn unit_line(self, line: &UnitLine<'_>, out: &mut Vec<PackedQuad>) -> u64 {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        {
            #[expect(
                unsafe_code,
                reason = "calls AVX-512 code; the token proves the CPU runs it"
            )]
            // SAFETY: as in `push_bits`.
            unsafe {
                kernels::unit_line_avx512(line, out)
            }
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        {
            let _ = (line, out);
            0
        }
    }
}

/// The AVX-512 code, compiled only where the target has vector registers.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
mod kernels {
    use alloc::vec::Vec;
    use core::mem::MaybeUninit;

    use core::arch::x86_64::{
        __m256i, __m512i, _mm_loadu_si128, _mm512_add_epi32, _mm512_add_epi64,
        _mm512_castsi512_si128, _mm512_castsi512_si256, _mm512_cmplt_epu64_mask,
        _mm512_cvtepu8_epi64, _mm512_cvtepu16_epi64, _mm512_cvtepu32_epi64,
        _mm512_extracti64x4_epi64, _mm512_mask_add_epi8, _mm512_mask_or_epi64,
        _mm512_maskz_compress_epi32, _mm512_maskz_compress_epi64, _mm512_maskz_mov_epi64,
        _mm512_permutexvar_epi64, _mm512_reduce_or_epi64, _mm512_set1_epi8, _mm512_set1_epi32,
        _mm512_set1_epi64, _mm512_setr_epi32, _mm512_setr_epi64, _mm512_setzero_si512,
        _mm512_slli_epi32, _mm512_slli_epi64, _mm512_sllv_epi64, _mm512_storeu_si512,
        _mm512_ternarylogic_epi64,
    };
    use voxel_core::formats::PackedQuad;

    use super::UnitLine;

    /// The candidate quads of bits `0..8`: `base + (j << shift)` in lane `j`.
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn first_lanes(base: u64, shift: u32) -> __m512i {
        let bit = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
        let shifted = _mm512_sllv_epi64(bit, _mm512_set1_epi64(i64::from(shift)));
        _mm512_add_epi64(_mm512_set1_epi64(base as i64), shifted)
    }

    /// Writes the quads of `lanes` whose bit is set in `mask`, in lane order, at `spare[n..]`,
    /// and returns the index after them. The store writes all 8 lanes: `spare` needs 8 entries
    /// from `n` on, and the next group's store overwrites the lanes not kept.
    #[target_feature(enable = "avx512f,popcnt")]
    #[inline]
    fn store_kept(
        spare: &mut [MaybeUninit<PackedQuad>],
        n: usize,
        mask: u8,
        lanes: __m512i,
    ) -> usize {
        let dst = &mut spare[n..n + 8];
        #[expect(unsafe_code, reason = "a 64-byte vector store")]
        // SAFETY: `dst` is 8 entries of 8 bytes, and an unaligned store needs no alignment.
        unsafe {
            _mm512_storeu_si512(
                dst.as_mut_ptr().cast(),
                _mm512_maskz_compress_epi64(mask, lanes),
            );
        }
        n + mask.count_ones() as usize
    }

    /// Makes room in `out` for the quads of the faces `bits` plus the spare lanes of the last
    /// store (see [`store_kept`]), and returns how many quads the faces make.
    #[inline(always)]
    fn reserve_line(out: &mut Vec<PackedQuad>, bits: u64) -> usize {
        let count = bits.count_ones() as usize;
        out.reserve(count + 8);
        count
    }

    /// See [`Wide::push_bits`].
    ///
    /// All the quads of a line differ only in the bit coordinate, so the kernel compresses
    /// shifted bit indices rather than quads: per group of 16 bits, `vpcompressd` keeps the
    /// 32-bit `b << SHIFT` of the set bits (a constant vector per group), which are widened to
    /// 64-bit lanes and added to `base`, 8 at a time; a group stores a second register only when
    /// it has more than 8 faces. A line of 31 faces (a checkerboard's) takes 4 compresses and
    /// 4 stores, against 8 of each for 8-bit groups of whole quads.
    #[target_feature(enable = "avx512f,popcnt")]
    pub(super) fn push_bits_avx512<const SHIFT: u32>(
        out: &mut Vec<PackedQuad>,
        bits: u64,
        base: u64,
    ) {
        let count = reserve_line(out, bits);
        let spare = out.spare_capacity_mut();
        let base = _mm512_set1_epi64(base as i64);
        let quads = |offsets: __m256i| _mm512_add_epi64(base, _mm512_cvtepu32_epi64(offsets));
        let mut n = 0;
        for group in 0..4 {
            let mask = (bits >> (16 * group)) as u16;
            let offsets = _mm512_slli_epi32::<SHIFT>(_mm512_add_epi32(
                _mm512_set1_epi32(16 * group),
                _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
            ));
            let kept = _mm512_maskz_compress_epi32(mask, offsets);
            store_quads(spare, n, quads(_mm512_castsi512_si256(kept)));
            let faces = mask.count_ones() as usize;
            if faces > 8 {
                store_quads(spare, n + 8, quads(_mm512_extracti64x4_epi64::<1>(kept)));
            }
            n += faces;
        }
        #[expect(unsafe_code, reason = "marks the quads written above as the vector's")]
        // SAFETY: the groups wrote the first `count` spare entries, each starting where the last
        // one's faces ended.
        unsafe {
            out.set_len(out.len() + count);
        }
    }

    /// Writes the 8 quads of `quads` at `spare[n..n + 8]` (the next store overwrites those
    /// past the group's faces).
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn store_quads(spare: &mut [MaybeUninit<PackedQuad>], n: usize, quads: __m512i) {
        let dst = &mut spare[n..n + 8];
        #[expect(unsafe_code, reason = "a 64-byte vector store")]
        // SAFETY: `dst` is 8 entries of 8 bytes, and an unaligned store needs no alignment.
        unsafe {
            _mm512_storeu_si512(dst.as_mut_ptr().cast(), quads);
        }
    }

    /// See [`Wide::unit_line`].
    ///
    /// Per group of 8 bits: the 8 ids widened to 64-bit lanes, the 8 AO bytes (one qword of a
    /// register of the line's 64, moved down by a permute) likewise, both
    /// shifted into word 1 and OR-ed with the position lanes in one ternary-logic instruction,
    /// then compressed and stored. The ids seen are OR-ed as `1 << id`, ids of 64 and more as
    /// bit 0 (as `seen_bit`).
    #[target_feature(enable = "avx512f,avx512bw,popcnt")]
    pub(super) fn unit_line_avx512(line: &UnitLine<'_>, out: &mut Vec<PackedQuad>) -> u64 {
        // The AO byte of bit b at byte b: plane k adds bit k where it is set.
        let mut ao_bytes = _mm512_setzero_si512();
        for (k, &plane) in line.ao.iter().enumerate() {
            ao_bytes = _mm512_mask_add_epi8(ao_bytes, plane, ao_bytes, _mm512_set1_epi8(1 << k));
        }
        let count = reserve_line(out, line.bits);
        let spare = out.spare_capacity_mut();
        let one = _mm512_set1_epi64(1);
        let step = _mm512_set1_epi64(8i64 << line.shift);
        let mut lanes = first_lanes(line.first.wrapping_sub(1 << line.shift), line.shift);
        let sixty_four = _mm512_set1_epi64(64);
        let mut seen = _mm512_setzero_si512();
        let mut n = 0;
        // Every lane holds the index of the group's 8 AO bytes (qword `group` of `ao_bytes`).
        let mut ao_qword = _mm512_setzero_si512();
        for (group, ids) in line.ids.chunks_exact(8).enumerate() {
            let mask = (line.bits >> (8 * group)) as u8;
            #[expect(unsafe_code, reason = "a 16-byte vector load")]
            // SAFETY: `ids` is 8 `u16`s (16 bytes); the load is unaligned.
            let ids = unsafe { _mm512_cvtepu16_epi64(_mm_loadu_si128(ids.as_ptr().cast())) };
            let ao = _mm512_cvtepu8_epi64(_mm512_castsi512_si128(_mm512_permutexvar_epi64(
                ao_qword, ao_bytes,
            )));
            ao_qword = _mm512_add_epi64(ao_qword, one);
            // word1 << 32 | word0, word 1 = id << 11 | ao << 3 | face.
            let quads = _mm512_ternarylogic_epi64::<0xFE>(
                lanes,
                _mm512_slli_epi64::<{ PackedQuad::WORD1_SHIFT + PackedQuad::BLOCK_SHIFT }>(ids),
                _mm512_slli_epi64::<{ PackedQuad::WORD1_SHIFT + PackedQuad::AO_SHIFT }>(ao),
            );
            let small = _mm512_maskz_mov_epi64(_mm512_cmplt_epu64_mask(ids, sixty_four), ids);
            seen = _mm512_mask_or_epi64(seen, mask, seen, _mm512_sllv_epi64(one, small));
            n = store_kept(spare, n, mask, quads);
            lanes = _mm512_add_epi64(lanes, step);
        }
        #[expect(unsafe_code, reason = "marks the quads written above as the vector's")]
        // SAFETY: as in `push_bits_avx512`.
        unsafe {
            out.set_len(out.len() + count);
        }
        _mm512_reduce_or_epi64(seen) as u64
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;

    use super::*;

    /// The quads of `line`, one face at a time, as the scalar loops build them.
    fn scalar(line: &UnitLine<'_>) -> (Vec<PackedQuad>, u64) {
        let mut seen = 0u64;
        let quads = (1..64)
            .filter(|b| line.bits >> b & 1 == 1)
            .map(|b| {
                let id = u32::from(line.ids[b]);
                seen |= 1 << if id < 64 { id } else { 0 };
                let ao = (0..8).fold(0u32, |ao, k| ao | (((line.ao[k] >> b) & 1) as u32) << k);
                let quad = PackedQuad::from_u64(line.first + ((b as u64 - 1) << line.shift));
                PackedQuad {
                    face_ao_block: quad.face_ao_block
                        | id << PackedQuad::BLOCK_SHIFT
                        | ao << PackedQuad::AO_SHIFT,
                    ..quad
                }
            })
            .collect();
        (quads, seen)
    }

    /// Every line shape the kernels meet, at the edges of the packed fields: ids 0, 63, 64 and
    /// 65535, AO bytes 0 and 255, faces in every group (bits 1 and 62 included) or in none,
    /// words whose position bits are all set, the three bit shifts; appended after a quad that
    /// must stay.
    #[test]
    fn the_kernels_write_the_scalar_quads() {
        let Some(wide) = Wide::new(InstructionSet::X86V4) else {
            return; // this CPU has no AVX-512: the kernels never run here
        };
        let ids: [u16; 64] = core::array::from_fn(|b| [0, 63, 64, 65535, 7, 1][b % 6]);
        let bit_sets = [
            0x7FFF_FFFF_FFFF_FFFE,
            0x4000_0000_0000_0002,
            0x5555_5555_5555_5554,
            0x0F0F_00F0_F0F0_0F00,
            // 9 faces in the first group of 16, 16 in the second.
            0x0000_FFFF_03FE,
            0,
        ];
        for bits in bit_sets {
            for shift in PackedQuad::POSITION_SHIFTS {
                for ao in [
                    [0; 8],
                    [u64::MAX; 8],
                    [0x0123_4567_89AB_CDEF, 0, u64::MAX, 5, 6, 7, 8, 9],
                ] {
                    // Every position bit set but the bit coordinate's, face 5.
                    let position = (1 << (PackedQuad::Z_SHIFT + PackedQuad::FIELD_BITS)) - 1;
                    let first = PackedQuad {
                        position_size: position & !(PackedQuad::FIELD_MASK << shift),
                        face_ao_block: 5,
                    }
                    .to_u64();
                    let line = UnitLine {
                        bits,
                        ids: &ids,
                        ao,
                        first,
                        shift,
                    };
                    let (want, want_seen) = scalar(&line);
                    let mut out = vec![PackedQuad::default()];
                    let seen = wide.unit_line(&line, &mut out);
                    assert_eq!(out[1..], want[..], "bits {bits:#x} shift {shift}");
                    assert_eq!(seen, want_seen, "bits {bits:#x} shift {shift}");

                    let key = 0x0FFF_FFFFu64;
                    let mut out = vec![PackedQuad::default()];
                    let base = (key << PackedQuad::WORD1_SHIFT | first).wrapping_sub(1 << shift);
                    assert!(wide.push_bits(&mut out, bits, base, shift));
                    let same_key: Vec<PackedQuad> = (1..64u64)
                        .filter(|b| bits >> b & 1 == 1)
                        .map(|b| {
                            let both =
                                (key << PackedQuad::WORD1_SHIFT | first) + ((b - 1) << shift);
                            PackedQuad::from_u64(both)
                        })
                        .collect();
                    assert_eq!(out[1..], same_key[..], "bits {bits:#x} shift {shift}");
                }
            }
        }
    }
}
