//! Turning the face lines of one slice into quads: one per face, or greedy with AO-safe merging.
//!
//! Every face has a *key*: its block id and (when AO is on) its 4 corner AO values, packed the
//! way `PackedQuad` word 1 holds them (AO at bits 3..11, id at bits 11..27): one voxel read
//! plus a 512-entry table lookup on 9 bits of the front slice's opaque lines. Two faces merge
//! only when their keys are equal, so a merged quad has one id and the same AO at every unit
//! face it covers, and its 4 corners take that AO: merging never changes the shading.
//!
//! The greedy pass is `block-mesh`'s algorithm on bits: take the first remaining face (lowest
//! line, then lowest bit), grow along the first axis while the next face is present and has the
//! same key, then grow along the second axis while the whole next row is present with that key,
//! and clear what the quad covers. Key comparisons are done once per face, when its key is
//! computed: per line, `along` marks the faces whose next face in the line has an equal key and
//! `across` those whose face in the next line does, so both growth steps are whole-line bit
//! operations (a run of equal keys is a run of ones) with no data-dependent loop over keys.
//!
//! Faces none of whose 4 neighbours has an equal key can only ever be 1 x 1 quads, whatever
//! order the greedy pass takes (a quad covering one would need an equal neighbour): once the
//! masks are known they are emitted straight away, and removing them changes no other quad.
//! On terrain they are most faces.
//!
//! Keys are computed and alone faces emitted from a flat list of the slice's faces
//! ([`Positions`]), not by looping over the bits of each line: a surface of a few faces per
//! line would otherwise cost a mispredicted loop exit per line and per pass.
//!
//! Unknown ids of the opaque layer are caught through a cache of the ids below 64 that passed,
//! one bit each, kept for the whole chunk: the passes that write 1 x 1 quads only OR each
//! face's id bit into a mask (and note an id of 64 or more), and compare it with the cache once
//! per slice or line; only a mask with a bit the cache lacks (or a large id) sends the faces
//! through the per-face check, which names the first unknown id and its position. Grown quads
//! are checked one by one.

use super::bits::nonzero_lines;
use super::faces::{Quads, SliceFaces};
use super::grow::{greedy_bits_first, greedy_lines_first};
use super::line_units::many;
use super::masks::Slice;
use super::positions::{Positions, line_bit};
use super::slices::Direction;
use crate::MeshError;

/// Scratch of the greedy pass for one slice: the key of every face by line and bit, per line
/// which neighbouring faces have equal keys, and the face lists of the passes (see
/// [`Positions`]). Only entries of faces (and of lines with faces) that take part in merging are
/// meaningful; everything is rewritten before it is read, so nothing is cleared between slices.
#[derive(Clone, Debug)]
pub(crate) struct Keys {
    /// Key by line and bit.
    pub(crate) keys: [[u32; 64]; 64],
    /// `along[l]` bit `b`: the faces at `(l, b)` and `(l, b + 1)` merge and have equal keys.
    pub(crate) along: Slice,
    /// `across[l]` bit `b`: the faces at `(l, b)` and `(l + 1, b)` merge and have equal keys.
    pub(crate) across: Slice,
    /// `alone[l]` bit `b`: the face at `(l, b)` has no neighbour with an equal key.
    alone: Slice,
    /// The faces of the slice, line by line.
    list: Positions,
    /// Ids below 64 known to the classes, one bit each (see [`SliceFaces::check`]); kept for a
    /// whole chunk, so a slice's first face does not miss the cache.
    pub(crate) known: u64,
}

impl Keys {
    /// Zeroed scratch.
    pub(crate) fn new() -> Self {
        Keys {
            keys: [[0; 64]; 64],
            along: [0; 64],
            across: [0; 64],
            alone: [0; 64],
            list: Positions::new(),
            known: 0,
        }
    }
}

/// Bit `l` set iff line `l` of `faces` has a face.
#[inline]
pub(crate) fn rows_of(faces: &Slice) -> u64 {
    nonzero_lines(faces)
}

/// One quad per face of the lines of `rows`; leaves `faces` empty.
pub(crate) fn unit_quads<const D: usize, const AO: bool>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    rows: u64,
    known: &mut u64,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    let mut rest = rows;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let f = faces[l & 63];
        // Many faces and none with a neighbouring face (a checkerboard): most share one key.
        if many(f) {
            let near = (f << 1) | (f >> 1) | faces[(l - 1) & 63] | faces[(l + 1) & 63];
            if f & near == 0 {
                s.line_units::<AO>(l, f, known, out)?;
                continue;
            }
        }
        s.units::<AO>(l, f, known, out)?;
    }
    *faces = [0; 64];
    Ok(())
}

/// Greedy quads for one slice whose faces lie in the lines of `rows`; leaves `faces` empty.
///
/// 1. Per line, without a branch: the faces of lines of fewer than [`many`] faces are listed
///    ([`Positions`]). Then per line of many faces: if none of them has a neighbouring face (a
///    checkerboard) they are emitted as 1 x 1 quads straight away, whatever the order of the
///    greedy pass; else the line is "dense".
/// 2. Per listed face: its key into the table, compared with the keys of the faces before it
///    in its line and in the line before (`along`, `across`, masked in step 3). Then per dense
///    line, in order, in a loop over its bits: its keys, compared with the faces before them
///    in the line and with both neighbouring lines; those `across` entries are replaced, since
///    the listed faces compared against the dense line's stale keys.
/// 3. Per line: faces none of whose 4 neighbours has an equal key (`alone`) can only ever be
///    1 x 1 quads, whatever the order of the greedy pass; they leave `faces`.
/// 4. Alone faces are written as 1 x 1 quads: per listed face, each written and the end moved
///    past the alone ones only (no branch per face); per dense line, a loop over its bits.
/// 5. The rest grows quads with bit operations on the masks: a run of equal keys is a run of
///    ones.
///
/// Sparse lines (terrain) go through the list so that a line costs no mispredicted loop exit;
/// dense ones (random fills) through per-line loops, whose exits are few per face.
pub(crate) fn greedy<const D: usize, const AO: bool>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    rows: u64,
    e: usize,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    let mut known = keys.known;
    let mut dense = 0u64;
    keys.list.clear();
    let mut crowded = 0u64;
    let mut rest = rows;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        keys.along[l & 63] = 0;
        keys.across[l & 63] = 0;
        keys.across[(l - 1) & 63] = 0;
        let f = faces[l & 63];
        // No branch: a crowded line lists nothing here.
        let is_crowded = many(f);
        crowded |= u64::from(is_crowded) << l;
        keys.list.push_line(l, if is_crowded { 0 } else { f });
    }
    let mut rest = crowded;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let f = faces[l & 63];
        let near = (f << 1) | (f >> 1) | faces[(l - 1) & 63] | faces[(l + 1) & 63];
        if f & near == 0 {
            s.line_units::<AO>(l, f, &mut known, out)?;
            faces[l & 63] = 0;
        } else {
            dense |= 1 << l;
        }
    }
    for &pos in keys.list.as_slice() {
        let (l, b) = line_bit(pos);
        let key = s.key::<AO>(l, b);
        keys.keys[l][b] = key;
        // Compared with stale entries too where there is no face (masked off below) or where
        // line l - 1 is dense (its keys come next, and overwrite this entry).
        let left_eq = keys.keys[l][(b - 1) & 63] == key;
        keys.along[l] |= u64::from(left_eq) << ((b - 1) & 63);
        let below_eq = keys.keys[(l - 1) & 63][b] == key;
        keys.across[(l - 1) & 63] |= u64::from(below_eq) << b;
    }
    let mut rest = dense;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        // Line l + 1's keys: final if it was listed, else computed next (and compared then).
        if dense >> (l + 1) & 1 == 0 {
            line_keys::<D, AO, true>(s, l, faces[l & 63], keys);
        } else {
            line_keys::<D, AO, false>(s, l, faces[l & 63], keys);
        }
    }
    let mut left = rows;
    let mut rest = rows;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let here = faces[l & 63];
        let along = keys.along[l & 63] & here & (here >> 1);
        let across = keys.across[l & 63] & here & faces[(l + 1) & 63];
        // Line l - 1 already went through this loop (or has no face): its entry is final.
        let below = keys.across[(l - 1) & 63] & faces[(l - 1) & 63] & here;
        keys.along[l & 63] = along;
        keys.across[l & 63] = across;
        let alone = here & !along & !(along << 1) & !across & !below;
        keys.alone[l & 63] = alone;
        faces[l & 63] = here & !alone;
        left &= !(u64::from(here == alone) << l);
    }
    // Ids seen (below 64, one bit each) and any of 64 or more, of every listed face and the
    // alone faces of dense lines: checked against the cache of known ids once, after both
    // loops, instead of once per face (every listed face shows, alone or in a grown quad).
    let mut seen = 0u64;
    let mut wide = 0u32;
    for &pos in keys.list.as_slice() {
        let (l, b) = line_bit(pos);
        let key = keys.keys[l][b];
        seen |= 1 << ((key >> 11) & 63);
        wide |= key >> 17;
        out.push_if(s.unit(l, b, key), (keys.alone[l] >> b) & 1 != 0);
    }
    let mut rest = dense;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let mut m = keys.alone[l & 63];
        while m != 0 {
            let b = m.trailing_zeros() as usize;
            m &= m - 1;
            let key = keys.keys[l & 63][b];
            seen |= 1 << ((key >> 11) & 63);
            wide |= key >> 17;
            out.push(s.unit(l, b, key));
        }
    }
    if seen & !known != 0 || wide != 0 {
        check_alone(s, keys, dense, &mut known)?;
    }
    let grown = if Direction::<D>::LINES_FIRST {
        greedy_lines_first(s, faces, e, left, keys, &mut known, out)
    } else {
        greedy_bits_first(s, faces, e, left, keys, &mut known, out)
    };
    keys.known = known;
    grown
}

/// Checks the id of every listed face, then of the alone faces of the `dense` lines: the slow
/// path of a slice with an id the cache of known ids does not hold yet.
#[cold]
fn check_alone<const D: usize>(
    s: &SliceFaces<'_, D>,
    keys: &Keys,
    dense: u64,
    known: &mut u64,
) -> Result<(), MeshError> {
    for &pos in keys.list.as_slice() {
        let (l, b) = line_bit(pos);
        s.check(keys.keys[l][b], known, l, b)?;
    }
    let mut rest = dense;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let mut m = keys.alone[l & 63];
        while m != 0 {
            let b = m.trailing_zeros() as usize;
            m &= m - 1;
            s.check(keys.keys[l & 63][b], known, l, b)?;
        }
    }
    Ok(())
}

/// Keys of the faces `f` of dense line `l` into the table, and their comparisons with the
/// faces before them in the line, with line `l - 1` and, with `ABOVE`, with line `l + 1`; these
/// replace the `across` entries of those lines. Line `l - 1`'s keys are final (listed lines
/// come first, dense ones in order); `ABOVE` is for a listed line `l + 1` (a dense one makes
/// the comparison itself when its turn comes).
#[inline(always)]
fn line_keys<const D: usize, const AO: bool, const ABOVE: bool>(
    s: &SliceFaces<'_, D>,
    l: usize,
    f: u64,
    keys: &mut Keys,
) {
    let row = s.row(l);
    let (f0, f1, f2) = s.front_lines(l);
    let mut along = 0u64;
    let mut below = 0u64;
    let mut above = 0u64;
    let mut m = f;
    while m != 0 {
        let b = m.trailing_zeros() as usize;
        m &= m - 1;
        let id = match row {
            Some(row) => u32::from(row[b & 63]),
            None => s.id(l, b),
        };
        let key = id << 11 | s.ao::<AO>((f0, f1, f2), b) << 3;
        keys.keys[l & 63][b & 63] = key;
        along |= u64::from(keys.keys[l & 63][(b - 1) & 63] == key) << ((b - 1) & 63);
        below |= u64::from(keys.keys[(l - 1) & 63][b & 63] == key) << (b & 63);
        if ABOVE {
            above |= u64::from(keys.keys[(l + 1) & 63][b & 63] == key) << (b & 63);
        }
    }
    keys.along[l & 63] |= along;
    keys.across[(l - 1) & 63] = below;
    if ABOVE {
        keys.across[l & 63] = above;
    }
}
