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
//! Unknown ids are checked once per face (greedy) or quad (one quad per face) of the opaque
//! layer; ids below 64 that passed are cached as bits, a test that stays predictable when
//! neighbouring faces alternate ids.

use voxel_core::BlockId;
use voxel_core::formats::PackedQuad;

use super::masks::Slice;
use super::positions::{Positions, line_bit};
use super::slices::Direction;
use crate::{BlockClasses, MeshError};

/// Scratch of the greedy pass for one slice: the key of every face by line and bit, per line
/// which neighbouring faces have equal keys, and the face lists of the passes (see
/// [`Positions`]). Only entries of faces (and of lines with faces) that take part in merging are
/// meaningful; everything is rewritten before it is read, so nothing is cleared between slices.
#[derive(Clone, Debug)]
pub(crate) struct Keys {
    /// Key by line and bit.
    keys: [[u32; 64]; 64],
    /// `along[l]` bit `b`: the faces at `(l, b)` and `(l, b + 1)` merge and have equal keys.
    along: Slice,
    /// `across[l]` bit `b`: the faces at `(l, b)` and `(l + 1, b)` merge and have equal keys.
    across: Slice,
    /// `alone[l]` bit `b`: the face at `(l, b)` has no neighbour with an equal key.
    alone: Slice,
    /// The faces of the slice, line by line.
    list: Positions,
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
        }
    }
}

/// The faces of one slice of direction `D`, as the merge passes see them.
pub(crate) struct SliceFaces<'a, const D: usize> {
    /// Padded ids, x fastest.
    pub voxels: &'a [u16],
    /// Index of the slice's voxel at line 0, bit 0.
    pub base: usize,
    /// Voxel index stride of one line.
    pub stride_l: usize,
    /// Voxel index stride of one bit.
    pub stride_b: usize,
    /// Opaque lines of the front slice (for AO).
    pub front: &'a Slice,
    /// The slice's padded coordinate.
    pub n: usize,
    /// Check that ids are known (opaque layer).
    pub check: Option<&'a BlockClasses>,
}

/// The opaque lines of the front slice around line `l`.
type Front = (u64, u64, u64);

/// Room for the quads of one slice (at most 62 x 62 faces), written in place and appended to
/// the output with one copy per slice, which keeps the loops free of the output vector's
/// length and capacity bookkeeping.
pub(crate) type SliceQuads = [PackedQuad; 4096];

/// The quads of the slice being meshed: the buffer and how many it holds.
pub(crate) struct Quads<'a> {
    /// The buffer.
    pub buf: &'a mut SliceQuads,
    /// Quads written so far.
    pub len: usize,
}

impl Quads<'_> {
    /// Appends one quad.
    #[inline(always)]
    fn push(&mut self, q: PackedQuad) {
        self.buf[self.len & 4095] = q;
        self.len += 1;
    }

    /// Writes `q` past the end, and keeps it (moves the end) only if `keep`: no branch.
    #[inline(always)]
    fn push_if(&mut self, q: PackedQuad, keep: bool) {
        self.buf[self.len & 4095] = q;
        self.len += usize::from(keep);
    }
}

impl<const D: usize> SliceFaces<'_, D> {
    /// The front lines around line `l`.
    #[inline(always)]
    fn front_lines(&self, l: usize) -> Front {
        (
            self.front[(l - 1) & 63],
            self.front[l & 63],
            self.front[(l + 1) & 63],
        )
    }

    /// The key of the face at line `l`, bit `b`: its id and, with `AO`, its 4 corner values.
    #[inline(always)]
    fn key<const AO: bool>(&self, l: usize, b: usize) -> u32 {
        let i = self.base + l * self.stride_l + b * self.stride_b;
        let id = u32::from(self.voxels.get(i).copied().unwrap_or(0));
        let ao = if AO {
            let s = (b - 1) & 63;
            let (f0, f1, f2) = self.front_lines(l);
            let code = ((f0 >> s) & 7) | ((f1 >> s) & 7) << 3 | ((f2 >> s) & 7) << 6;
            u32::from(Direction::<D>::AO_TABLE[(code & 511) as usize])
        } else {
            0xFF
        };
        id << 11 | ao << 3
    }

    /// Word 0 of a quad at line `l`, bit `b`, spanning `lines` lines and `bits` bits.
    #[inline(always)]
    fn position_size(&self, l: usize, b: usize, lines: usize, bits: usize) -> u32 {
        ((self.n as u32 - 1) << Direction::<D>::SHIFT_N)
            | ((l as u32 - 1) << Direction::<D>::SHIFT_L)
            | ((b as u32 - 1) << Direction::<D>::SHIFT_B)
            | ((lines as u32 - 1) << Direction::<D>::SIZE_SHIFT_L)
            | ((bits as u32 - 1) << Direction::<D>::SIZE_SHIFT_B)
    }

    /// Fails if the layer is checked and the id of `key` is unknown; `known` caches, one bit
    /// each, the ids below 64 that passed (a test that stays predictable when ids alternate).
    #[inline(always)]
    fn check(&self, key: u32, known: &mut u64, l: usize, b: usize) -> Result<(), MeshError> {
        let id = key >> 11;
        if id < 64 && (*known >> id) & 1 != 0 {
            return Ok(());
        }
        let Some(classes) = self.check else {
            return Ok(());
        };
        let id = BlockId(id as u16);
        if classes.class(id).is_some() {
            if id.0 < 64 {
                *known |= 1 << id.0;
            }
            return Ok(());
        }
        let mut position = [0u32; 3];
        position[(Direction::<D>::SHIFT_N / 6) as usize] = self.n as u32;
        position[(Direction::<D>::SHIFT_L / 6) as usize] = l as u32;
        position[(Direction::<D>::SHIFT_B / 6) as usize] = b as u32;
        Err(MeshError::UnknownBlock { id, position })
    }

    /// The 1 x 1 quad of the face at line `l`, bit `b`, with `key`.
    #[inline(always)]
    fn unit(&self, l: usize, b: usize, key: u32) -> PackedQuad {
        PackedQuad {
            position_size: self.position_size(l, b, 1, 1),
            face_ao_block: key | D as u32,
        }
    }

    /// Pushes the quad at line `l`, bit `b`, spanning `lines` lines and `bits` bits.
    #[inline(always)]
    fn push(
        &self,
        out: &mut Quads<'_>,
        known: &mut u64,
        (l, b, lines, bits): (usize, usize, usize, usize),
        key: u32,
    ) -> Result<(), MeshError> {
        self.check(key, known, l, b)?;
        out.push(PackedQuad {
            position_size: self.position_size(l, b, lines, bits),
            face_ao_block: key | D as u32,
        });
        Ok(())
    }
}

/// Bit `l` set iff line `l` of `faces` has a face.
#[inline]
pub(crate) fn rows_of(faces: &Slice) -> u64 {
    faces
        .iter()
        .enumerate()
        .fold(0, |rows, (l, &f)| rows | u64::from(f != 0) << l)
}

/// Lists the faces of the lines of `rows`.
#[inline(always)]
fn list_faces(faces: &mut Slice, rows: u64, list: &mut Positions) {
    list.clear();
    let mut rest = rows;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        list.push_line(l, faces[l & 63]);
    }
}

/// One quad per face of the lines of `rows`; leaves `faces` empty.
pub(crate) fn unit_quads<const D: usize, const AO: bool>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    rows: u64,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    list_faces(faces, rows, &mut keys.list);
    let mut known = 0u64;
    for &pos in keys.list.as_slice() {
        let (l, b) = line_bit(pos);
        s.push(out, &mut known, (l, b, 1, 1), s.key::<AO>(l, b))?;
    }
    *faces = [0; 64];
    Ok(())
}

/// Greedy quads for one slice whose faces lie in the lines of `rows`; leaves `faces` empty.
///
/// 1. The faces are listed line by line ([`Positions`]).
/// 2. Per listed face: its key into the table, and whether it equals the keys of the faces
///    before it in its line and in the line before (`along`, `across`, masked in step 3).
/// 3. Per line: faces none of whose 4 neighbours has an equal key (`alone`) can only ever be
///    1 x 1 quads, whatever the order of the greedy pass; they leave `faces`.
/// 4. Per listed face: every key is checked, and the alone faces are written as 1 x 1 quads
///    (each face written, the end moved past the alone ones only: no branch per face).
/// 5. The rest grows quads with bit operations on the masks: a run of equal keys is a run of
///    ones.
pub(crate) fn greedy<const D: usize, const AO: bool>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    rows: u64,
    e: usize,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    list_faces(faces, rows, &mut keys.list);
    let mut rest = rows;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        keys.along[l & 63] = 0;
        keys.across[l & 63] = 0;
        keys.across[(l - 1) & 63] = 0;
    }
    for &pos in keys.list.as_slice() {
        let (l, b) = line_bit(pos);
        let key = s.key::<AO>(l, b);
        keys.keys[l][b] = key;
        // Compared with stale entries too where there is no face: masked off below.
        let left_eq = keys.keys[l][(b - 1) & 63] == key;
        keys.along[l] |= u64::from(left_eq) << ((b - 1) & 63);
        let below_eq = keys.keys[(l - 1) & 63][b] == key;
        keys.across[(l - 1) & 63] |= u64::from(below_eq) << b;
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
    let mut known = 0u64;
    for &pos in keys.list.as_slice() {
        let (l, b) = line_bit(pos);
        let key = keys.keys[l][b];
        s.check(key, &mut known, l, b)?;
        out.push_if(s.unit(l, b, key), (keys.alone[l] >> b) & 1 != 0);
    }
    if Direction::<D>::LINES_FIRST {
        greedy_lines_first(s, faces, e, left, keys, &mut known, out)
    } else {
        greedy_bits_first(s, faces, e, left, keys, &mut known, out)
    }
}

/// Greedy quads growing along bits first, then lines (the ±Z faces), starting from the lines
/// of `left`; leaves `faces` empty.
fn greedy_bits_first<const D: usize>(
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
        let row = &keys.keys[l & 63];
        while here != 0 {
            let b = here.trailing_zeros() as usize;
            let key = row[b & 63];
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
fn greedy_lines_first<const D: usize>(
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
            let key = keys.keys[l & 63][b & 63];
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
