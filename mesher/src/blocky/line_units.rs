//! The fast path for a line with many faces to emit as 1 x 1 quads: every face of a
//! checkerboard, a long exposed row of faces that do not merge.
//!
//! Per face, the generic path reads the id, builds the 9-bit front neighbourhood and looks its
//! AO up. On such a line most faces usually share one key, so the line is split with whole-line
//! bit operations first:
//!
//! - faces whose 3 x 3 front neighbourhood equals the first face's share its AO: 9 bit planes
//!   (each front line shifted by -1, 0, +1), each compared with the first face's bit;
//! - where the bits run along x (±Y and ±Z faces) the ids of the line are a contiguous row, and
//!   the faces with the first face's id come from one SIMD compare of the row.
//!
//! - ±X faces have their ids strided: those with the first face's AO are read one by one and
//!   compared with its id without a branch.
//!
//! Faces with the first face's key take one add and one store each; the others take the
//! generic path.

use voxel_core::formats::PackedQuad;

use super::bits::{faces_of_id, masked, ones};
use super::faces::{LineIds, Quads, SliceFaces, UnitLine};
use super::masks::Front;
use super::memo::NeighbourhoodMemo;
use crate::MeshError;

/// Faces from which a line of 1 x 1 quads is written straight into the output (see
/// [`SliceFaces::units`]).
const DIRECT_MIN: u32 = 12;

impl<const A: usize> SliceFaces<'_, A> {
    /// The bits of a line with front lines `(f0, f1, f2)` whose front neighbourhood, the 9 bits
    /// [`key`](Self::key) reads, equals that of bit `b0`.
    #[inline(always)]
    fn same_neighbourhood((f0, f1, f2): Front, b0: usize) -> u64 {
        let mut same = u64::MAX;
        for f in [f0, f1, f2] {
            // Bit b of each plane: the front voxel at bit offset -1, 0, +1 of face b.
            for plane in [f << 1, f, f >> 1] {
                let want = 0u64.wrapping_sub((plane >> b0) & 1);
                same &= !(plane ^ want);
            }
        }
        same
    }

    /// Appends a 1 x 1 quad for every face of `bits` in line `l`, the line's id row and front
    /// lines read once.
    ///
    /// Lines of [`DIRECT_MIN`] faces or more are written straight into the output, which
    /// saves copying them out of the slice's buffer
    /// but costs a capacity check per line: shorter lines go through the buffer. The rule
    /// does not depend on the instruction set, so neither does the order of the quads.
    #[inline(always)]
    pub(crate) fn units<const AO: bool>(
        &self,
        l: usize,
        bits: u64,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        if bits.count_ones() >= DIRECT_MIN {
            return self.units_direct::<AO>(l, bits, out);
        }
        let ids = self.line_ids(l);
        let front = self.front_lines(l);
        let line = self.unit_line(l);
        // The end in a local: the buffer's end is stored once, not once per quad (on an error
        // the whole output is dropped).
        let mut n = out.len;
        // The largest id: checked once, after the line, instead of once per face.
        let mut seen = 0u32;
        for b in ones(bits) {
            let (quad, id) = self.unit_quad::<AO>(ids, front, line, b);
            seen = seen.max(id);
            out.buf[masked::<4096>(n)] = quad;
            n += 1;
        }
        if seen >= self.known_below {
            self.check_line(l, bits)?;
        }
        out.len = n;
        Ok(())
    }

    /// The 1 x 1 quad of the face at bit `b` (at least 1) of a line with ids `ids`, front
    /// lines `front` and quads `line`, and the face's id.
    #[inline(always)]
    fn unit_quad<const AO: bool>(
        &self,
        ids: LineIds<'_>,
        front: Front,
        line: UnitLine,
        b: usize,
    ) -> (PackedQuad, u32) {
        let id = ids.id(b);
        let key = id << PackedQuad::BLOCK_SHIFT
            | self.ao::<AO>(front, b) << PackedQuad::AO_SHIFT
            | self.facing.face_bits;
        (line.quad(b, key), id)
    }

    /// [`units`](Self::units) straight into the output.
    #[inline(always)]
    fn units_direct<const AO: bool>(
        &self,
        l: usize,
        bits: u64,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        let ids = self.line_ids(l);
        let front = self.front_lines(l);
        let line = self.unit_line(l);
        let mut seen = 0u32;
        let mut m = bits;
        // One capacity check for the line (as `push_bits`): `extend` from a range knows its
        // length, an iterator of the bits (`bits::ones`) would not, so the bits are scanned
        // by hand.
        out.out.extend((0..bits.count_ones()).map(|_| {
            let b = m.trailing_zeros() as usize;
            m &= m.wrapping_sub(1);
            let (quad, id) = self.unit_quad::<AO>(ids, front, line, b);
            seen = seen.max(id);
            quad
        }));
        if seen >= self.known_below {
            self.check_line(l, bits)?;
        }
        Ok(())
    }

    /// [`check`](Self::check)s the id of every face of `bits` in line `l`: the slow path of a
    /// line with an id the classes may not know.
    #[cold]
    fn check_line(&self, l: usize, bits: u64) -> Result<(), MeshError> {
        for b in ones(bits) {
            self.check(self.id(l, b) << PackedQuad::BLOCK_SHIFT, l, b)?;
        }
        Ok(())
    }

    /// Appends a 1 x 1 quad for every face of `bits` (not empty) in line `l`, a line with
    /// [`many`](super::bits::many) faces: faces that share the first face's key cost one add
    /// and one store each.
    #[inline(always)]
    pub(crate) fn line_units<const AO: bool>(
        &self,
        l: usize,
        bits: u64,
        memo: &mut NeighbourhoodMemo<Front>,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        let b0 = masked::<64>(bits.trailing_zeros() as usize);
        let (same_ao, key0) = if AO {
            let front = self.front_lines(l);
            let (same, ao0) = memo.split(&front, b0, || {
                (
                    Self::same_neighbourhood(front, b0),
                    self.ao::<AO>(front, b0),
                )
            });
            let id0 = self.id(l, b0);
            (
                same & bits,
                id0 << PackedQuad::BLOCK_SHIFT | ao0 << PackedQuad::AO_SHIFT,
            )
        } else {
            (bits, self.key::<AO>(l, b0))
        };
        let ids = self.line_ids(l);
        let same_key = match ids {
            // A 32^3 chunk's faces lie in the first 48 ids (three whole SIMD registers).
            LineIds::Row(row) => match row.first_chunk::<48>() {
                Some(short) if self.short => faces_of_id(short, row[b0], same_ao),
                _ => faces_of_id(row, row[b0], same_ao),
            },
            // ±X faces: the ids are strided, read one by one but compared without a branch.
            LineIds::Strided { .. } => {
                let id0 = key0 >> PackedQuad::BLOCK_SHIFT;
                let mut differ = 0u64;
                for b in ones(same_ao) {
                    differ |= u64::from(ids.id(b) != id0) << b;
                }
                same_ao & !differ
            }
        };
        self.check(key0, l, b0)?;
        let key = key0 | self.facing.face_bits;
        out.push_bits(same_key, self.unit_line(l), key);
        let rest = bits & !same_key;
        if rest == 0 {
            return Ok(());
        }
        self.units::<AO>(l, rest, out)
    }
}
