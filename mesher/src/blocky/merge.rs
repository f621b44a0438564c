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
//! removing them changes no other quad. On terrain they are most faces, on random fills
//! nearly all. So [`greedy`] computes every key first, then writes those *alone* faces as
//! 1 x 1 quads in one tight loop, and grows quads from the other faces only. (Writing every
//! face as a quad while keying it, then taking back the quads of faces that merge, gains on
//! random fills but loses on terrain once the keying loop is compiled for BMI2.)
//!
//! Where the keys come from is the const parameter `K` of the passes (see `keys::FROM_TABLE`):
//!
//! - keyed face by face into the table (AO on, and AO off where the next two do not apply);
//! - in a one-id chunk with AO off every face has the key `Keys::one`: step 1 is skipped, and
//!   the equal-key masks are the masks of neighbouring faces;
//! - with AO off in a chunk with dense exposed rows, the equal-key masks are the chunk's
//!   equal-id masks (`super::equal`), built by SIMD row compares before any slice: step 1 is
//!   skipped, and a quad's key is its origin's id, read from the voxels when it is written.
//!
//! Unknown ids of the opaque layer are caught with one compare per line or slice: a palette's
//! ids run from 0 without a gap, so the passes that write 1 x 1 quads keep the largest id they
//! wrote and compare it with the classes' bound (`known_below`) once; only a larger id sends
//! the faces through the per-face check, which names the first unknown id and its position.
//! The greedy pass keys (and so checks) every face before it writes any quad, so its grown
//! quads need no check of their own.

use voxel_core::formats::PackedQuad;

use super::bits::{many, masked, nonzero_lines, ones, rows_equal};
use super::direction::Axis;
use super::faces::{Quads, SliceFaces};
use super::grow::{greedy_bits_first, greedy_lines_first};
use super::keys::{FROM_IDS, FROM_ONE, Keys, key_bits};
use super::masks::Slice;
use crate::MeshError;

/// Bit `l` set iff line `l` of `faces` has a face.
#[inline(always)]
pub(crate) fn rows_of(faces: &Slice) -> u64 {
    nonzero_lines(faces)
}

/// One quad per face of the lines of `rows`; leaves `faces` empty.
#[inline(always)]
pub(crate) fn unit_quads<const A: usize, const AO: bool, const ONE: bool>(
    s: &SliceFaces<'_, A>,
    faces: &mut Slice,
    rows: u64,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    if ONE {
        // Every face has the one key: each line's quads in bulk.
        for l in ones(rows) {
            out.push_bits(
                faces[l],
                s.unit_line(l),
                keys.one | key_bits::<AO>(s.facing),
            );
        }
        *faces = [0; 64];
        return Ok(());
    }
    let mut lines = ones(rows);
    while let Some(l) = lines.next() {
        if let Some(next) = lines.peek() {
            s.prefetch_line(next);
        }
        let f = faces[l];
        // Many faces and none with a neighbouring face (a checkerboard): most share one key.
        if many_lone(faces, l) {
            s.line_units::<AO>(l, f, &mut keys.memo, out)?;
            continue;
        }
        s.units::<AO>(l, f, out)?;
    }
    *faces = [0; 64];
    Ok(())
}

/// Greedy quads for one slice whose faces lie in the lines of `rows`; leaves `faces` empty.
///
/// 1. Per line: a line of [`many`] faces none of which has a neighbouring face (a checkerboard
///    stripe) is emitted through the bulk path; every other face has its key stored and
///    compared with the face before it in its line and the face in the line before (`along`,
///    `across`: stale where there is no face, masked in step 2). Ids are checked once for the
///    slice.
/// 2. Per line: the faces with no neighbour of an equal key (`alone`) leave `faces`.
/// 3. The alone faces are written as 1 x 1 quads (with AO off, from the lines that have one,
///    see [`lone_first`]).
/// 4. The other faces grow quads with bit operations on the masks: a run of equal keys is a
///    run of ones.
#[inline(always)]
pub(crate) fn greedy<const A: usize, const AO: bool, const K: u8>(
    s: &SliceFaces<'_, A>,
    faces: &mut Slice,
    rows: u64,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    const { assert!(K != FROM_IDS || !AO) };
    // A one-id chunk's faces, and faces merged by the chunk's equal-id masks, need no keying.
    let rows = match K {
        FROM_ONE | FROM_IDS => rows,
        _ => key_slice::<A, AO>(s, faces, rows, keys, out)?,
    };
    let one = K == FROM_ONE;
    let mut left = 0u64;
    let mut lone_rows = 0u64;
    for l in ones(rows) {
        let here = faces[l];
        // Bit b: face b has the key of the face after it in the line (the keyed masks say
        // "of the one before"). With `FROM_ONE` every pair of faces has equal keys.
        let along_next = match K {
            FROM_ONE => u64::MAX,
            FROM_IDS => s.equal_along(l),
            _ => keys.along[l] >> 1,
        };
        let along = along_next & here & (here >> 1);
        let across_keys = match K {
            FROM_ONE => u64::MAX,
            FROM_IDS => s.equal_across(l),
            _ => keys.across[l],
        };
        let across = across_keys & here & faces[masked::<64>(l + 1)];
        // Line l - 1 already went through this loop (or has no face): its entry is final.
        let below_keys = if one {
            u64::MAX
        } else {
            keys.across[masked::<64>(l - 1)]
        };
        let below = below_keys & faces[masked::<64>(l - 1)] & here;
        keys.along[l] = along;
        keys.across[l] = across;
        let alone = here & !along & !(along << 1) & !across & !below;
        keys.alone[l] = alone;
        faces[l] = here & !alone;
        left |= u64::from(here != alone) << l;
        if lone_first::<AO, K>() {
            lone_rows |= u64::from(alone != 0) << l;
        }
    }
    let alone_rows = if lone_first::<AO, K>() {
        lone_rows
    } else {
        rows
    };
    emit_alone::<A, AO, K>(s, alone_rows, keys, out);
    if Axis::<A>::LINES_FIRST {
        greedy_lines_first::<A, AO, K>(s, faces, left, keys, out);
    } else {
        greedy_bits_first::<A, AO, K>(s, faces, left, keys, out);
    }
    Ok(())
}

/// Step 1 of [`greedy`]: keys every face of the lines `rows` (or emits lines of many lone
/// faces through the bulk path, taking them out of `faces`) and checks the ids; returns the
/// lines left with keyed faces.
#[inline(always)]
fn key_slice<const A: usize, const AO: bool>(
    s: &SliceFaces<'_, A>,
    faces: &mut Slice,
    rows: u64,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<u64, MeshError> {
    let mut lone_lines = 0u64;
    // The largest id keyed.
    let mut seen = 0u32;
    let mut lines = ones(rows);
    while let Some(l) = lines.next() {
        if let Some(next) = lines.peek() {
            s.prefetch_line(next);
        }
        let f = faces[l];
        if many_lone(faces, l) {
            s.line_units::<AO>(l, f, &mut keys.memo, out)?;
            faces[l] = 0;
            lone_lines |= 1 << l;
            continue;
        }
        keyed_line::<A, AO>(s, l, f, keys, &mut seen);
    }
    let rows = rows & !lone_lines;
    if seen >= s.known_below {
        check_faces(s, faces, rows, keys)?;
    }
    Ok(rows)
}

/// The keys of the faces `f` of line `l` into the table, each compared with the face before it
/// in the line and the face in line `l - 1` (`along[l]` bit `b`: face `b` has the key of the
/// face before it; `across[l - 1]`: stale entries where there is no face, masked later). The
/// largest id goes into `seen`.
///
/// Written for few live values (two row pointers and one bit index for the key table, the
/// previous key in a register), so that the loop runs with few spills: it is most of the
/// greedy mesher's time.
#[inline(always)]
fn keyed_line<const A: usize, const AO: bool>(
    s: &SliceFaces<'_, A>,
    l: usize,
    f: u64,
    keys: &mut Keys,
    seen: &mut u32,
) {
    if !AO && f.count_ones() >= ROW_KEYED_MIN && keyed_row(s, l, keys, seen) {
        return;
    }
    let ids = s.line_ids(l);
    let front = s.front_lines(l);
    // Two row pointers: the line's keys and the line before's, one bit index into both.
    let (before, here) = keys.keys.split_at_mut(l);
    let here = &mut here[0];
    let before = before.last().unwrap_or(&[0; 64]);
    let mut along = 0u64;
    let mut below = 0u64;
    // No key is all ones (ids have 16 bits): the line's first face equals no previous one.
    let mut previous = u32::MAX;
    let mut seen_here = 0u32;
    for b in ones(f) {
        let id = ids.id(b);
        seen_here = seen_here.max(id);
        let key = if AO {
            id << PackedQuad::BLOCK_SHIFT | s.ao::<AO>(front, b) << PackedQuad::AO_SHIFT
        } else {
            id << PackedQuad::BLOCK_SHIFT
        };
        here[b] = key;
        along |= u64::from(previous == key) << b;
        previous = key;
        below |= u64::from(before[b] == key) << b;
    }
    *seen = (*seen).max(seen_here);
    keys.along[l] = along;
    keys.across[masked::<64>(l - 1)] = below;
}

/// Faces from which a line's keys are all taken at once by [`keyed_row`] (AO off).
const ROW_KEYED_MIN: u32 = 8;

/// [`keyed_line`] with AO off for a line whose ids are a row in memory (the ±Y and ±Z faces),
/// all 64 bits at once, with no loop over the faces: the keys are the ids, `along` compares
/// the row with itself one id earlier and `across` with the line before's row. Entries where
/// there is no face are stale, as in `keyed_line`, and masked later. `seen` takes the row's
/// largest id, faces or not: a larger id than the faces' only sends the slice through the
/// exact per-face check. False (nothing done) for the ±X faces, whose ids are strided, and
/// at the ids' far end, where a shifted row would run past them.
#[inline(always)]
fn keyed_row<const A: usize>(
    s: &SliceFaces<'_, A>,
    l: usize,
    keys: &mut Keys,
    seen: &mut u32,
) -> bool {
    let (Some(row), Some(earlier), Some(before)) = (
        s.row_ids(l, 0),
        s.row_ids(l, -1),
        s.row_ids(masked::<64>(l - 1), 0),
    ) else {
        return false;
    };
    for (key, &id) in keys.keys[l].iter_mut().zip(row) {
        *key = u32::from(id) << PackedQuad::BLOCK_SHIFT;
    }
    keys.along[l] = rows_equal(row, earlier);
    keys.across[masked::<64>(l - 1)] = rows_equal(row, before);
    *seen = (*seen).max(u32::from(row.iter().fold(0, |m, &id| m.max(id))));
    true
}

/// Checks the id of every face of the lines `rows` (keys in the table): the slow path of a
/// slice with an id the classes may not know.
#[cold]
fn check_faces<const A: usize>(
    s: &SliceFaces<'_, A>,
    faces: &Slice,
    rows: u64,
    keys: &Keys,
) -> Result<(), MeshError> {
    let mut result = Ok(());
    each_face(rows, faces, |l, b| {
        if result.is_ok() {
            result = s.check(keys.key(l, b), l, b);
        }
    });
    result
}

/// Whether [`emit_alone`] takes only lines with an alone face and writes each one's first
/// before its loop: with AO off and keys that differ (a one-id chunk's faces have few alone
/// faces, and those on few lines).
const fn lone_first<const AO: bool, const K: u8>() -> bool {
    !AO && K != FROM_ONE
}

/// The 1 x 1 quads of the alone faces of the lines `rows` (keys from where `K` says). Where
/// [`lone_first`], `rows` holds only lines with an alone face (see [`greedy`]).
#[inline(always)]
fn emit_alone<const A: usize, const AO: bool, const K: u8>(
    s: &SliceFaces<'_, A>,
    rows: u64,
    keys: &Keys,
    out: &mut Quads<'_>,
) {
    let mut n = out.len;
    for l in ones(rows) {
        let line = s.unit_line(l);
        let quad = |b: usize| line.quad(b, s.key_of::<K>(keys, l, b) | key_bits::<AO>(s.facing));
        let mut bits = keys.alone[l];
        if lone_first::<AO, K>() {
            // With AO off most of these lines have one alone face: it is written before the
            // loop, which then mostly runs no step. A loop over every alone face of the line
            // would end after a count that changes from line to line, and its end would be
            // mispredicted often.
            debug_assert!(bits != 0, "line {l} was taken for an alone face");
            out.buf[masked::<4096>(n)] = quad(bits.trailing_zeros() as usize);
            n += 1;
            bits &= bits.wrapping_sub(1);
        }
        for b in ones(bits) {
            out.buf[masked::<4096>(n)] = quad(b);
            n += 1;
        }
    }
    out.len = n;
}

/// True when line `l` has [`many`] faces and none of them has a neighbouring face in the
/// slice (a checkerboard stripe): the lines the bulk path takes.
#[inline(always)]
fn many_lone(faces: &Slice, l: usize) -> bool {
    let f = faces[l];
    many(f)
        && f & ((f << 1) | (f >> 1) | faces[masked::<64>(l - 1)] | faces[masked::<64>(l + 1)]) == 0
}

/// Calls `f(l, b)` for every set bit `b` of `masks[l]`, for the lines `l` of `rows` in order.
#[inline(always)]
fn each_face(rows: u64, masks: &Slice, mut f: impl FnMut(usize, usize)) {
    for l in ones(rows) {
        for b in ones(masks[l]) {
            f(l, b);
        }
    }
}
