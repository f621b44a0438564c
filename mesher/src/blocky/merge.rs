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
//! Faces with no neighbouring face in the slice (found per line with two shifts and three ORs)
//! can only ever be 1 x 1 quads, whatever order the greedy pass takes: they are emitted
//! straight away, without a key table entry. So are, once the masks are known, faces none of
//! whose 4 neighbours has an equal key (a quad covering one would need an equal neighbour);
//! removing them changes no other quad.
//!
//! Unknown ids are checked once per quad of the opaque layer; ids below 64 that passed are
//! cached as bits, a test that stays predictable when neighbouring faces alternate ids.

use voxel_core::BlockId;
use voxel_core::formats::PackedQuad;

use super::masks::Slice;
use super::slices::Direction;
use crate::{BlockClasses, MeshError};

/// Scratch of the greedy pass for one slice: the key of every face by line and bit, and per
/// line which neighbouring faces have equal keys. Only entries of faces (and of lines with
/// faces) that take part in merging are meaningful; everything is rewritten before it is read,
/// so nothing is cleared between slices.
#[derive(Clone, Debug)]
pub(crate) struct Keys {
    /// Key by line and bit.
    keys: [[u32; 64]; 64],
    /// `along[l]` bit `b`: the faces at `(l, b)` and `(l, b + 1)` merge and have equal keys.
    along: Slice,
    /// `across[l]` bit `b`: the faces at `(l, b)` and `(l + 1, b)` merge and have equal keys.
    across: Slice,
}

impl Keys {
    /// Zeroed scratch.
    pub(crate) fn new() -> Self {
        Keys {
            keys: [[0; 64]; 64],
            along: [0; 64],
            across: [0; 64],
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

    /// The ids of the line whose voxel 0 is at index `line`, as a 64-id row when the bits run
    /// along x (contiguous ids: ±Y and ±Z faces) and the row fits in the array.
    #[inline(always)]
    fn row(&self, line: usize) -> Option<&[u16; 64]> {
        if Direction::<D>::LAYOUT == 2 {
            return None;
        }
        self.voxels
            .get(line..line + 64)
            .and_then(|r| <&[u16; 64]>::try_from(r).ok())
    }

    /// The id at bit `b` of the line whose voxel 0 is at index `line`, `row` its ids if
    /// [`row`](Self::row) gave them.
    #[inline(always)]
    fn id(&self, row: Option<&[u16; 64]>, line: usize, b: usize) -> u32 {
        u32::from(match row {
            Some(row) => row[b & 63],
            None => self
                .voxels
                .get(line + b * self.stride_b)
                .copied()
                .unwrap_or(0),
        })
    }

    /// The key of the face at bit `b` of the line whose voxel 0 is at index `line`.
    #[inline(always)]
    fn key<const AO: bool>(
        &self,
        row: Option<&[u16; 64]>,
        line: usize,
        b: usize,
        front: Front,
    ) -> u32 {
        let id = self.id(row, line, b);
        let ao = if AO {
            let s = (b - 1) & 63;
            let (f0, f1, f2) = front;
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

    /// Appends a 1 x 1 quad for every face of `bits` in line `l`, computing keys on the way.
    #[inline(always)]
    fn units<const AO: bool>(
        &self,
        l: usize,
        mut bits: u64,
        known: &mut u64,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        let line = self.base + l * self.stride_l;
        let row = self.row(line);
        let front = self.front_lines(l);
        let word = self.position_size(l, 1, 1, 1);
        while bits != 0 {
            let b = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let key = self.key::<AO>(row, line, b, front);
            self.check(key, known, l, b)?;
            out.push(PackedQuad {
                position_size: word | ((b as u32 - 1) << Direction::<D>::SHIFT_B),
                face_ao_block: key | D as u32,
            });
        }
        Ok(())
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

/// One quad per face of lines `1..=e`; leaves `faces` empty.
pub(crate) fn unit_quads<const D: usize, const AO: bool>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    e: usize,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    let mut known = 0u64;
    #[expect(
        clippy::range_plus_one,
        reason = "`Range` iterates faster than `RangeInclusive`"
    )]
    for l in 1..e + 1 {
        let bits = core::mem::take(&mut faces[l & 63]);
        if bits != 0 {
            s.units::<AO>(l, bits, &mut known, out)?;
        }
    }
    Ok(())
}

/// Greedy quads for one slice; leaves `faces` empty.
///
/// First pass, line by line: faces with no neighbouring face are emitted as 1 x 1 quads; the
/// others get their key and the equal-key masks (`along`, `across`). Second pass: faces none of
/// whose 4 neighbours has an equal key can only ever be 1 x 1 quads too, whatever the order;
/// they are emitted from their stored key. The rest grows quads with bit operations on the
/// masks: a run of equal keys is a run of ones.
pub(crate) fn greedy<const D: usize, const AO: bool>(
    s: &SliceFaces<'_, D>,
    faces: &mut Slice,
    e: usize,
    keys: &mut Keys,
    out: &mut Quads<'_>,
) -> Result<(), MeshError> {
    let mut known = 0u64;
    let mut left = 0u64;
    #[expect(
        clippy::range_plus_one,
        reason = "`Range` iterates faster than `RangeInclusive`"
    )]
    for l in 1..e + 1 {
        let f = faces[l & 63];
        if f == 0 {
            continue;
        }
        let near = (f << 1) | (f >> 1) | faces[(l - 1) & 63] | faces[(l + 1) & 63];
        let lone = f & !near;
        if lone != 0 {
            s.units::<AO>(l, lone, &mut known, out)?;
        }
        let present = f & near;
        faces[l & 63] = present;
        if present == 0 {
            continue;
        }
        left |= 1 << l;
        let line = s.base + l * s.stride_l;
        let ids = s.row(line);
        let front = s.front_lines(l);
        let mut bits = present;
        let mut along = 0u64;
        let mut across = 0u64;
        while bits != 0 {
            let b = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let key = s.key::<AO>(ids, line, b, front);
            keys.keys[l & 63][b & 63] = key;
            along |= u64::from(keys.keys[l & 63][(b - 1) & 63] == key) << ((b - 1) & 63);
            across |= u64::from(keys.keys[(l - 1) & 63][b & 63] == key) << (b & 63);
        }
        keys.along[l & 63] = along & present & (present >> 1);
        keys.across[(l - 1) & 63] = across & present & faces[(l - 1) & 63];
        // Rewritten by line l + 1 if it has faces that merge.
        keys.across[l & 63] = 0;
    }
    // Faces with no equal-key neighbour.
    let mut rest = left;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let here = faces[l & 63];
        let along = keys.along[l & 63];
        let alone =
            here & !along & !(along << 1) & !keys.across[l & 63] & !keys.across[(l - 1) & 63];
        if alone == 0 {
            continue;
        }
        faces[l & 63] = here & !alone;
        if here == alone {
            left &= !(1 << l);
        }
        let row = &keys.keys[l & 63];
        let mut bits = alone;
        while bits != 0 {
            let b = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            s.push(out, &mut known, (l, b, 1, 1), row[b & 63])?;
        }
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
