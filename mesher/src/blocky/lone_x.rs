//! ±X faces with no neighbouring face, emitted from the occupancy rows (layout `A`: one `u64`
//! per padded x-row) instead of layout `C`.
//!
//! In layout `C` a line of ±X faces runs along z, so the ids of its faces lie a slab apart
//! (one cache line each). A face with no neighbouring face in its slice (up, down, left or
//! right) is a 1 x 1 quad whatever the merge order, and everything it needs is in the rows:
//!
//! - its x-row of faces is `row & !(row >> 1)` (+X) or `row & !(row << 1)` (-X), and its 4
//!   neighbours in the slice are the same bits of the face rows of `(y ± 1, z)`, `(y, z ± 1)`;
//! - its id is in the row's run of contiguous ids;
//! - its 9 front voxels (layer x ± 1, y and z ± 1) are bit x ± 1 of 9 occupancy rows: 9 bit
//!   planes, as [`super::line_units`] builds from layout `C`, with line = y and bit = z.
//!
//! So rows with [`many`] such faces are emitted here (faces sharing a key in bulk), and the
//! layout-`C` pass leaves those faces out of the opaque layer ([`drop_handled`]). On a
//! checkerboard that is every ±X face. The scan costs a few microseconds, which terrain (a
//! handful of lone faces per row at most) or a random fill would pay for little: it runs only
//! when a sample slab, the middle one, has a row of many faces that are all lone. Either way
//! the output is the same.
//!
//! It runs with AO on, and from padded edge [`ROWS_FROM`] on: only there does it pay (see
//! there).

use voxel_core::BlockId;
use voxel_core::formats::PackedQuad;

use super::bits::{faces_of_id, many, masked, ones};
use super::direction::Facing;
use super::faces::{Quads, UnitLine};
use super::input::Input;
use super::masks::Slice;
use super::memo::NeighbourhoodMemo;
use crate::{BlockClasses, MeshError};

/// The smallest padded edge at which [`lone_x`] runs (with AO on only):
///
/// - with AO off the walks' own paths for lone faces cost less than its sample and rows,
///   even on a checkerboard, where every face is a lone one;
/// - below 32^3 its sample and rows cost more than they spare, AO on as well.
pub(crate) const ROWS_FROM: usize = 34;

/// Removes, in place, the faces of a slice that `lone_x` emitted: those with no neighbouring
/// face whose line `l` and bit are set in `handled` (its rows of many lone faces, by y and z).
#[inline(always)]
pub(crate) fn drop_handled(faces: &mut Slice, handled: &Slice) {
    let old = *faces;
    // Lines 0 and 63 hold no face (padding): skipping them keeps `l - 1` and `l + 1` in range.
    debug_assert!(old[0] == 0 && old[63] == 0);
    for l in 1..63 {
        let f = old[l];
        let lone = f & !((f << 1) | (f >> 1) | old[l - 1] | old[l + 1]);
        faces[l] &= !(lone & handled[l]);
    }
}

/// The ±X faces (direction `D`) of a z-slab of occupancy rows, row by row (none on the
/// padding rows, or in a padding slab when `inside` is false), into lines `0..e + 2` of `out`
/// (the slab's own lines: the rest of a short chunk's slab is zero, and reading it would
/// fetch cold cache lines; `out`'s lines past them stay as they are).
#[inline(always)]
fn slab_faces<const D: usize>(slab: &Slice, inner: u64, e: usize, inside: bool, out: &mut Slice) {
    let rows = u64::MAX >> (63 - e) & !1;
    for (y, (f, &row)) in out.iter_mut().zip(&slab[..e + 2]).enumerate() {
        let front = if Facing::of(D).positive {
            row >> 1
        } else {
            row << 1
        };
        let keep = u64::from(inside && (rows >> y) & 1 != 0);
        *f = row & !front & inner & 0u64.wrapping_sub(keep);
    }
}

/// Emits the opaque ±X faces (direction `D`, 0 or 1) that have no neighbouring face and lie in
/// rows of [`many`] such faces, as 1 x 1 quads with AO, into `out` (flushed slab by slab: a
/// slab has at most 62 x 31 such faces); marks those rows in
/// `handled` (bit z of line y). Does nothing with AO off, below padded edge [`ROWS_FROM`], or
/// unless the middle slab has a row of many faces that are all lone. Returns whether it
/// marked a row: `handled` is written, and read, only when the sample passes, so that most
/// chunks neither clear nor scan it.
#[inline(always)]
pub(crate) fn lone_x<const D: usize>(
    input: &Input<'_>,
    classes: &BlockClasses,
    out: &mut Quads<'_>,
    handled: &mut Slice,
) -> Result<bool, MeshError> {
    const ZERO: Slice = [0; 64];
    let p = input.p;
    if !input.ao || p < ROWS_FROM {
        return Ok(false);
    }
    let e = p - 2;
    let inner = (u64::MAX >> (64 - e)) << 1;
    let a = input.opaque.by[0];
    let slab = |z: usize| a.get(z).unwrap_or(&ZERO);
    // Face rows of slabs z - 1, z and z + 1.
    let mut below = [0u64; 64];
    let mut here = [0u64; 64];
    let mut above = [0u64; 64];
    let lone_rows = |below: &Slice, here: &Slice, above: &Slice, y: usize| {
        let near = here[masked::<64>(y - 1)]
            | here[masked::<64>(y + 1)]
            | below[masked::<64>(y)]
            | above[masked::<64>(y)];
        here[masked::<64>(y)] & !near
    };
    // The sample: the middle slab.
    let mid = e / 2 + 1;
    slab_faces::<D>(slab(mid - 1), inner, e, mid > 1, &mut below);
    slab_faces::<D>(slab(mid), inner, e, true, &mut here);
    slab_faces::<D>(slab(mid + 1), inner, e, mid < e, &mut above);
    // Rows whose faces are all lone, and many: random fills (a few lone faces in most rows)
    // would pay the whole scan for little.
    let all_lone = |y: usize| {
        let lone = lone_rows(&below, &here, &above, y);
        many(lone) && lone == here[masked::<64>(y)]
    };
    if !(1..=e).any(all_lone) {
        return Ok(false);
    }
    // The rows are gathered here and stored at the end: `handled` is scratch the compiler
    // cannot keep apart from `out`, so that marking it in the loop would reload both.
    let mut rows: Slice = [0; 64];
    below = [0; 64];
    slab_faces::<D>(slab(1), inner, e, true, &mut here);
    let known_below = classes.known_below();
    let mut memo = NeighbourhoodMemo::new();
    // The ids read for a row: its own, and for a 32^3 chunk the next ones up to 48 where the
    // array has them (the faces lie in bits 1..=32 only, and 48 ids fill three SIMD
    // registers, see `faces_of_id`).
    let row_len = if p <= 48 { 48 } else { p };
    for z in 1..=e {
        slab_faces::<D>(slab(z + 1), inner, e, z < e, &mut above);
        for y in 1..=e {
            let lone = lone_rows(&below, &here, &above, y);
            if !many(lone) {
                continue;
            }
            rows[masked::<64>(y)] |= 1 << z;
            // Plane 3r + c, bit x: the front voxel of the face at x, at y + r - 1, z + c - 1
            // (layout C's line and bit offsets, as the AO table reads them).
            let planes: [u64; 9] = core::array::from_fn(|k| {
                let row = slab(z + k % 3 - 1)[masked::<64>(y + k / 3 - 1)];
                if Facing::of(D).positive {
                    row >> 1
                } else {
                    row << 1
                }
            });
            let start = (y + p * z) * p;
            let end = (start + row_len).min(input.voxels.len());
            let ids = input.voxels.get(start..end).unwrap_or(&[]);
            emit_row::<D>([y, z], lone, &planes, ids, known_below, &mut memo, out)?;
        }
        out.flush();
        below = here;
        here = above;
    }
    *handled = rows;
    Ok(rows.iter().any(|&r| r != 0))
}

/// Emits the faces `bits` of row `(y, z)`, whose ids are `ids` (x-indexed) and whose front
/// neighbourhoods are `planes`, with AO.
#[inline(always)]
fn emit_row<const D: usize>(
    [y, z]: [usize; 2],
    bits: u64,
    planes: &[u64; 9],
    ids: &[u16],
    known_below: u32,
    memo: &mut NeighbourhoodMemo<[u64; 9]>,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    let code = |x: usize| {
        planes.iter().enumerate().fold(0usize, |code, (k, &plane)| {
            code | (((plane >> x) & 1) as usize) << k
        })
    };
    let ao_of = |code: usize| u32::from(Facing::of(D).ao_table[code]);
    let key_of = |id: u16, code: usize| {
        u32::from(id) << PackedQuad::BLOCK_SHIFT
            | ao_of(code) << PackedQuad::AO_SHIFT
            | Facing::of(D).face_bits
    };
    let key = |x: usize| key_of(ids.get(x).copied().unwrap_or(0), code(x));
    let check = |key: u32, x: usize| {
        let id = key >> PackedQuad::BLOCK_SHIFT;
        if id < known_below {
            return Ok(());
        }
        Err(MeshError::UnknownBlock {
            id: BlockId(id as u16),
            position: [x as u32, y as u32, z as u32],
        })
    };
    // The faces' quads: chunk-local x, y, z; width and height 1; bits along x.
    let line = UnitLine {
        first: ((y - 1) << PackedQuad::Y_SHIFT | (z - 1) << PackedQuad::Z_SHIFT) as u32,
        shift: PackedQuad::X_SHIFT,
    };
    let mut rest = bits;
    {
        // Faces with the first face's front neighbourhood and id share its key. One pass over
        // the planes gives both the first face's neighbourhood code and the faces that share it
        // (or the memo has them from a row with the same planes).
        let x0 = masked::<64>(bits.trailing_zeros() as usize);
        let (same, ao0) = memo.split(planes, x0, || {
            let mut same = u64::MAX;
            let mut code0 = 0;
            for (k, &plane) in planes.iter().enumerate() {
                let bit = (plane >> x0) & 1;
                code0 |= (bit as usize) << k;
                same &= !(plane ^ 0u64.wrapping_sub(bit));
            }
            (same, ao_of(code0))
        });
        let id0 = ids.get(x0).copied().unwrap_or(0);
        let key0 = u32::from(id0) << PackedQuad::BLOCK_SHIFT
            | ao0 << PackedQuad::AO_SHIFT
            | Facing::of(D).face_bits;
        let same = faces_of_id(ids, id0, same & bits);
        check(key0, x0)?;
        out.push_bits(same, line, key0);
        rest &= !same;
    }
    for x in ones(rest) {
        let k = key(x);
        check(k, x)?;
        out.push(line.quad(x, k));
    }
    Ok(())
}
