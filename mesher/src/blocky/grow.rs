//! Growing greedy quads from the equal-key masks, in `block-mesh`'s order: along bits first
//! (the ±X and ±Z faces) or along lines first (the ±Y faces), from origins taken line by line
//! (±Y, ±Z) or bit by bit (±X, whose bits run along `block-mesh`'s slowest scan axis).
//!
//! The faces' ids were checked when they were keyed, so growing cannot fail. Line 0 and the
//! lines past the chunk hold no face, so a quad stops growing there without a bound check.

use super::bits::{masked, ones};
use super::direction::Axis;
use super::faces::{Quads, SliceFaces};
use super::keys::{Keys, key_bits};
use super::masks::Slice;

/// Greedy quads growing along bits first, then lines (the ±X and ±Z faces), from the faces of
/// the lines of `left`; leaves `faces` empty. Quads start at the lowest line, then the lowest
/// bit, or, for [`Axis::BIT_MAJOR`] directions, at the lowest bit, then the lowest line.
#[inline(always)]
pub(crate) fn greedy_bits_first<const A: usize, const AO: bool, const K: u8>(
    s: &SliceFaces<'_, A>,
    faces: &mut Slice,
    left: u64,
    keys: &Keys,
    out: &mut Quads<'_>,
) {
    if Axis::<A>::BIT_MAJOR {
        // The faces as columns (`columns[b]` bit `l`: a face at line `l`, bit `b`), so a bit's
        // origins are the set bits of one word: those whose face is still there (not taken by
        // a quad from an earlier bit or line). This costs a few operations per face; a pass
        // over every line with faces for every bit cost far more on slices with many merging
        // faces (AO off).
        let mut columns: Slice = [0; 64];
        let mut any = 0u64;
        for l in ones(left) {
            let m = faces[l];
            any |= m;
            for b in ones(m) {
                columns[b] |= 1 << l;
            }
        }
        for b in ones(any) {
            for l in ones(columns[b]) {
                if (faces[l] >> b) & 1 != 0 {
                    grow_bits_first::<A, AO, K>(s, faces, (l, b), keys, out);
                }
            }
        }
        return;
    }
    for l in ones(left) {
        // Origins line by line: no quad from an earlier origin holds a face below this line
        // within this quad's bits (it would hold the face above it too), so the lines below
        // are read from the equal-key masks alone, and this line's faces stay in a register.
        let mut here = faces[l];
        while here != 0 {
            let b = here.trailing_zeros() as usize;
            let chain = (keys.along[l] & here & (here >> 1)) >> b;
            let (bits, mask) = run_of(chain, b);
            here &= !mask;
            let mut lines = 1;
            while keys.across[masked::<64>(l + lines - 1)] & mask == mask {
                faces[masked::<64>(l + lines)] &= !mask;
                lines += 1;
            }
            s.push(
                out,
                (l, b, lines, bits),
                s.key_of::<K>(keys, l, b) | key_bits::<AO>(s.facing),
            );
        }
        faces[l] = 0;
    }
}

/// Grows one quad from the face at line `l`, bit `b`: along bits while the next face is
/// present with an equal key, then along lines while the whole next row is; takes its faces
/// out of `faces` and writes it. For the bit-major directions, whose quads from earlier bits
/// may have taken faces in the lines below.
#[inline(always)]
fn grow_bits_first<const A: usize, const AO: bool, const K: u8>(
    s: &SliceFaces<'_, A>,
    faces: &mut Slice,
    (l, b): (usize, usize),
    keys: &Keys,
    out: &mut Quads<'_>,
) {
    let key = s.key_of::<K>(keys, l, b);
    let here = faces[l];
    // Faces still present from b on with the same key.
    let chain = (keys.along[l] & here & (here >> 1)) >> b;
    let (bits, mask) = run_of(chain, b);
    faces[l] &= !mask;
    let mut lines = 1;
    while faces[masked::<64>(l + lines)] & mask == mask
        && keys.across[masked::<64>(l + lines - 1)] & mask == mask
    {
        faces[masked::<64>(l + lines)] &= !mask;
        lines += 1;
    }
    s.push(out, (l, b, lines, bits), key | key_bits::<AO>(s.facing));
}

/// Greedy quads growing along lines first, then bits (the ±Y faces), starting from the lines
/// of `left`; leaves `faces` empty.
#[inline(always)]
pub(crate) fn greedy_lines_first<const A: usize, const AO: bool, const K: u8>(
    s: &SliceFaces<'_, A>,
    faces: &mut Slice,
    left: u64,
    keys: &Keys,
    out: &mut Quads<'_>,
) {
    for l in ones(left) {
        let mut here = faces[l];
        let along = keys.along[l];
        while here != 0 {
            let b = here.trailing_zeros() as usize;
            let key = s.key_of::<K>(keys, l, b);
            let bit = 1u64 << b;
            let mut lines = 1;
            // Bit j: faces b + j and b + j + 1 present with equal keys in every line so far.
            let mut chain = (along & here & (here >> 1)) >> b;
            // The lines below are read from the equal-key masks alone: they only hold faces
            // present with equal keys (see `merge::greedy`), and no quad from an earlier
            // origin holds one of this column's faces below this line, or one of the row's
            // faces up to where the row ends (it would hold the face above it too).
            while keys.across[masked::<64>(l + lines - 1)] & bit != 0 {
                chain &= keys.along[masked::<64>(l + lines)] >> b;
                lines += 1;
            }
            let (bits, mask) = run_of(chain, b);
            here &= !mask;
            for f in faces.iter_mut().take(l + lines).skip(l + 1) {
                *f &= !mask;
            }
            s.push(out, (l, b, lines, bits), key | key_bits::<AO>(s.facing));
        }
        faces[l] = 0;
    }
}

/// The faces of a quad's row starting at bit `b`, given `chain` (bit `j`: faces `b + j` and
/// `b + j + 1` merge): how many, and their mask. The row ends at the lowest zero of `chain`,
/// and `x ^ (x - 1)` keeps the bits up to the lowest one of `x` (one BMI instruction).
#[inline(always)]
fn run_of(chain: u64, b: usize) -> (usize, u64) {
    let ends = !chain;
    let row = ends ^ ends.wrapping_sub(1);
    (row.count_ones() as usize, row << b)
}
