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
//! order the greedy pass takes (a quad covering one would need an equal neighbour), and
//! removing them changes no other quad. On terrain they are most faces (73 %), on random fills
//! nearly all. So [`greedy`] first writes *every* face as a 1 x 1 quad while it computes the
//! keys (the loop of the one-quad-per-face mesher, plus a key store and two compares per face),
//! then finds the faces that do have an equal neighbour, takes their quads back out (the order
//! of quads carries no meaning, so a hole can be filled with the last quad), and grows quads
//! from those faces only. Where most faces merge (flat models, no AO) that first write is
//! wasted: after a slice in which most lines had faces to grow, the next slice of that
//! direction computes keys only and writes the alone faces afterwards.
//!
//! Unknown ids of the opaque layer are caught through a cache of the ids below 64 that passed,
//! one bit each, kept for the whole chunk: the passes that write 1 x 1 quads only OR each
//! face's id bit into a mask (and note an id of 64 or more), and compare it with the cache once
//! per slice or line; only a mask with a bit the cache lacks (or a large id) sends the faces
//! through the per-face check, which names the first unknown id and its position. Grown quads
//! are checked one by one.

use voxel_core::formats::PackedQuad;

use super::bits::nonzero_lines;
use super::faces::{Quads, SliceFaces};
use super::grow::{greedy_bits_first, greedy_lines_first};
use super::line_units::many;
use super::masks::Slice;
use super::slices::Direction;
use crate::MeshError;

/// Scratch of the greedy pass for one slice: the key of every face by line and bit, per line
/// which neighbouring faces have equal keys, and where each face's 1 x 1 quad was written.
/// Only entries of faces (and of lines with faces) are meaningful; everything is rewritten
/// before it is read, so nothing is cleared between slices.
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
    /// Where the 1 x 1 quad of the face at `(l, b)` is in the slice's quad buffer.
    at: [[u16; 64]; 64],
    /// Per direction: write every face of the next slice as a 1 x 1 quad before knowing
    /// whether it merges (see [`greedy`]); reset for every chunk.
    pub(crate) speculate: [bool; 6],
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
            at: [[0; 64]; 64],
            speculate: [true; 6],
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
        if many_lone(faces, l) {
            s.line_units::<AO>(l, f, known, out)?;
            continue;
        }
        s.units::<AO>(l, f, known, out)?;
    }
    *faces = [0; 64];
    Ok(())
}

/// Greedy quads for one slice whose faces lie in the lines of `rows`; leaves `faces` empty.
///
/// 1. Per line: a line of [`many`] faces none of which has a neighbouring face (a checkerboard
///    stripe) is emitted through the bulk path; every other face is written as a 1 x 1 quad
///    (unless the previous slice of this direction mostly merged), its key stored and compared
///    with the faces before it in its line and in the line before (`along`, `across`: stale
///    where there is no face, masked in step 2). Ids are checked once for the slice.
/// 2. Per line: the faces with no neighbour of an equal key (`alone`) keep their quads and
///    leave `faces`.
/// 3. The quads of the other faces are taken back out: each hole filled with the last quad
///    when few lines have such faces (terrain, random fills), else by one pass that keeps the
///    alone faces' quads. Without quads written in step 1, the alone faces are written now.
/// 4. Those faces grow quads with bit operations on the masks: a run of equal keys is a run of
///    ones.
pub(crate) fn greedy<const D: usize, const AO: bool>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    rows: u64,
    e: usize,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    let mut known = keys.known;
    let first = out.len;
    let speculate = keys.speculate[D];
    let mut lone_lines = 0u64;
    let mut seen = 0u64;
    let mut wide = 0u32;
    let mut rest = rows;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let f = faces[l & 63];
        if many_lone(faces, l) {
            // All alone: some of their quads may be in the buffer (faces whose key is not the
            // line's first), which step 3 must keep.
            s.line_units::<AO>(l, f, &mut known, out)?;
            faces[l & 63] = 0;
            keys.alone[l & 63] = f;
            lone_lines |= 1 << l;
            continue;
        }
        if speculate {
            keyed_units::<D, AO, true>(s, l, f, keys, out, &mut seen, &mut wide);
        } else {
            keyed_units::<D, AO, false>(s, l, f, keys, out, &mut seen, &mut wide);
        }
    }
    if seen & !known != 0 || wide >= 64 {
        check_faces(s, faces, rows & !lone_lines, keys, &mut known)?;
    }
    keys.known = known;
    let mut left = 0u64;
    let mut rest = rows & !lone_lines;
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
        left |= u64::from(here != alone) << l;
    }
    // Most lines have faces that merge: the next slice probably too, and then writing every
    // face first costs more than it saves.
    let mostly_merging = 2 * left.count_ones() > rows.count_ones();
    keys.speculate[D] = !mostly_merging;
    if !speculate {
        emit_alone(s, rows & !lone_lines, keys, out);
    } else if left == 0 {
        return Ok(());
    } else if mostly_merging {
        // Most lines have faces to grow: keep the quads of alone faces, in one pass.
        let mut kept = first;
        for i in first..out.len {
            let q = out.buf[i & 4095];
            let l = (q.position_size >> Direction::<D>::SHIFT_L) as usize + 1;
            let b = (q.position_size >> Direction::<D>::SHIFT_B) as usize + 1;
            out.buf[kept & 4095] = q;
            kept += ((keys.alone[l & 63] >> (b & 63)) & 1) as usize;
        }
        out.len = kept;
    } else {
        // Few faces to grow: take their quads out, each hole filled with the last quad.
        let mut len = out.len;
        let at = &mut keys.at;
        each_face(left, faces, |l, b| {
            let hole = at[l & 63][b & 63];
            len -= 1;
            let last = out.buf[len & 4095];
            out.buf[usize::from(hole) & 4095] = last;
            let ll = (last.position_size >> Direction::<D>::SHIFT_L) as usize + 1;
            let lb = (last.position_size >> Direction::<D>::SHIFT_B) as usize + 1;
            at[ll & 63][lb & 63] = hole;
        });
        out.len = len;
    }
    let mut known = keys.known;
    let grown = if Direction::<D>::LINES_FIRST {
        greedy_lines_first(s, faces, e, left, keys, &mut known, out)
    } else {
        greedy_bits_first(s, faces, e, left, keys, &mut known, out)
    };
    keys.known = known;
    grown
}

/// The faces `f` of line `l` as 1 x 1 quads, their keys into the table and compared with the
/// faces before them in the line and in line `l - 1` (`along[l]`, `across[l - 1]`: stale
/// entries where there is no face, masked later).
#[inline(always)]
fn keyed_units<const D: usize, const AO: bool, const QUADS: bool>(
    s: &SliceFaces<'_, D>,
    l: usize,
    f: u64,
    keys: &mut Keys,
    out: &mut Quads<'_>,
    seen: &mut u64,
    wide: &mut u32,
) {
    let row = s.row(l);
    let (f0, f1, f2) = s.front_lines(l);
    let word = s.position_size(l, 1, 1, 1);
    let mut along = 0u64;
    let mut below = 0u64;
    let mut n = out.len;
    let mut m = f;
    while m != 0 {
        let b = m.trailing_zeros() as usize;
        m &= m - 1;
        let id = match row {
            Some(row) => u32::from(row[b & 63]),
            None => s.id(l, b),
        };
        *seen |= 1 << (id & 63);
        *wide |= id;
        let key = id << 11 | s.ao::<AO>((f0, f1, f2), b) << 3;
        keys.keys[l & 63][b & 63] = key;
        along |= u64::from(keys.keys[l & 63][(b - 1) & 63] == key) << ((b - 1) & 63);
        below |= u64::from(keys.keys[(l - 1) & 63][b & 63] == key) << (b & 63);
        if QUADS {
            keys.at[l & 63][b & 63] = n as u16;
            out.buf[n & 4095] = PackedQuad {
                position_size: word | ((b as u32 - 1) << Direction::<D>::SHIFT_B),
                face_ao_block: key | D as u32,
            };
            n += 1;
        }
    }
    out.len = n;
    keys.along[l & 63] = along;
    keys.across[(l - 1) & 63] = below;
}

/// Checks the id of every face of the lines `rows` (keys in the table): the slow path of a
/// slice with an id the cache of known ids does not hold yet.
#[cold]
fn check_faces<const D: usize>(
    s: &SliceFaces<'_, D>,
    faces: &Slice,
    rows: u64,
    keys: &Keys,
    known: &mut u64,
) -> Result<(), MeshError> {
    let mut result = Ok(());
    each_face(rows, faces, |l, b| {
        if result.is_ok() {
            result = s.check(keys.keys[l & 63][b & 63], known, l, b);
        }
    });
    result
}

/// The 1 x 1 quads of the alone faces of the lines `rows`, for a slice whose faces were not
/// written as quads first.
fn emit_alone<const D: usize>(s: &SliceFaces<'_, D>, rows: u64, keys: &Keys, out: &mut Quads<'_>) {
    each_face(rows, &keys.alone, |l, b| {
        out.push(PackedQuad {
            position_size: s.position_size(l, b, 1, 1),
            face_ao_block: keys.keys[l & 63][b & 63] | D as u32,
        });
    });
}

/// True when line `l` has [`many`] faces and none of them has a neighbouring face in the
/// slice (a checkerboard stripe): the lines the bulk path takes.
#[inline(always)]
fn many_lone(faces: &Slice, l: usize) -> bool {
    let f = faces[l & 63];
    many(f) && f & ((f << 1) | (f >> 1) | faces[(l - 1) & 63] | faces[(l + 1) & 63]) == 0
}

/// Calls `f(l, b)` for every set bit `b` of `masks[l]`, for the lines `l` of `rows` in order.
#[inline(always)]
fn each_face(rows: u64, masks: &Slice, mut f: impl FnMut(usize, usize)) {
    let mut rest = rows;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let mut m = masks[l & 63];
        while m != 0 {
            let b = m.trailing_zeros() as usize;
            m &= m - 1;
            f(l, b);
        }
    }
}
