//! Growing greedy quads from the equal-key masks, in `block-mesh`'s order: along bits first
//! (the ±Z faces) or along lines first (the ±X and ±Y faces).

use super::faces::{Quads, SliceFaces};
use super::masks::Slice;
use super::merge::Keys;
use crate::MeshError;

/// Greedy quads growing along bits first, then lines (the ±Z faces), starting from the lines
/// of `left`; leaves `faces` empty.
#[inline(always)]
pub(crate) fn greedy_bits_first<const D: usize>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    e: usize,
    mut left: u64,
    keys: &Keys,
    known: &mut u64,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    while left != 0 {
        let l = left.trailing_zeros() as usize;
        left &= left - 1;
        let mut here = faces[l & 63];
        let along = keys.along[l & 63];
        while here != 0 {
            let b = here.trailing_zeros() as usize;
            let key = keys.key(l, b);
            // Faces still present from b on with the same key.
            let chain = (along & here & (here >> 1)) >> b;
            let bits = 1 + chain.trailing_ones() as usize;
            let mask = (u64::MAX >> ((64 - bits) & 63)) << b;
            here &= !mask;
            let mut lines = 1;
            while l + lines <= e
                && faces[(l + lines) & 63] & mask == mask
                && keys.across[(l + lines - 1) & 63] & mask == mask
            {
                faces[(l + lines) & 63] &= !mask;
                lines += 1;
            }
            s.push(out, known, (l, b, lines, bits), key)?;
        }
        faces[l & 63] = 0;
    }
    Ok(())
}

/// Greedy quads growing along lines first, then bits (the ±X and ±Y faces), starting from the
/// lines of `left`; leaves `faces` empty.
#[inline(always)]
pub(crate) fn greedy_lines_first<const D: usize>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    e: usize,
    mut left: u64,
    keys: &Keys,
    known: &mut u64,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    while left != 0 {
        let l = left.trailing_zeros() as usize;
        left &= left - 1;
        let mut here = faces[l & 63];
        let along = keys.along[l & 63];
        while here != 0 {
            let b = here.trailing_zeros() as usize;
            let key = keys.key(l, b);
            let bit = 1u64 << b;
            let mut lines = 1;
            // Bit j: faces b + j and b + j + 1 present with equal keys in every line so far.
            let mut chain = (along & here & (here >> 1)) >> b;
            while l + lines <= e
                && faces[(l + lines) & 63] & bit != 0
                && keys.across[(l + lines - 1) & 63] & bit != 0
            {
                let f = faces[(l + lines) & 63];
                chain &= (keys.along[(l + lines) & 63] & f & (f >> 1)) >> b;
                lines += 1;
            }
            let bits = 1 + chain.trailing_ones() as usize;
            let mask = (u64::MAX >> ((64 - bits) & 63)) << b;
            here &= !mask;
            for k in l + 1..l + lines {
                faces[k & 63] &= !mask;
            }
            s.push(out, known, (l, b, lines, bits), key)?;
        }
        faces[l & 63] = 0;
    }
    Ok(())
}
