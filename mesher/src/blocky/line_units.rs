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

use super::ao::{CORNER_OFFSETS, ao_planes};
use super::bits::faces_of_id;
use super::faces::{Front, LineIds, Quads, SliceFaces};
use super::slices::Direction;
use super::wide::{UnitLine, Wide};
use crate::MeshError;

/// True if `bits` has at least 4 set bits (without `popcnt`, which the baseline x86-64 target
/// lacks): the lines worth the fast path's fixed cost.
#[inline(always)]
pub(crate) fn many(bits: u64) -> bool {
    let mut x = bits & bits.wrapping_sub(1);
    x &= x.wrapping_sub(1);
    x &= x.wrapping_sub(1);
    x != 0
}

/// The front voxels a line's AO split is computed from: its 3 front lines here, its 9 bit
/// planes in [`super::lone_x`].
pub(crate) trait FrontVoxels: Copy {
    /// A value no line has in an entry with first bit 64 (never matched).
    const NONE: Self;
    /// Equal front voxels. Written as one OR of XORs for the planes: an array comparison
    /// compiles to a call.
    fn same_as(&self, other: &Self) -> bool;
}

impl FrontVoxels for Front {
    const NONE: Self = (0, 0, 0);

    #[inline(always)]
    fn same_as(&self, other: &Self) -> bool {
        ((self.0 ^ other.0) | (self.1 ^ other.1) | (self.2 ^ other.2)) == 0
    }
}

impl FrontVoxels for [u64; 9] {
    const NONE: Self = [0; 9];

    #[inline(always)]
    fn same_as(&self, other: &Self) -> bool {
        self.iter()
            .zip(other)
            .fold(0, |differ, (a, b)| differ | (a ^ b))
            == 0
    }
}

/// The AO split of the last two lines of lone faces met: the bits whose front neighbourhood
/// equals that of the line's first face, and that face's AO byte, by front voxels and first
/// bit. Two entries, because periodic slices (a checkerboard's, or stripes) repeat their lines
/// every other line; a hit saves the 9 bit-plane comparisons (7 % of a checkerboard's time).
#[derive(Clone, Copy, Debug)]
pub(crate) struct NeighbourhoodMemo<F> {
    /// Front voxels, first bit (64: an empty entry), same-neighbourhood bits, AO byte.
    entries: [(F, usize, u64, u32); 2],
    /// The entry the next miss replaces.
    next: usize,
}

impl<F: FrontVoxels> NeighbourhoodMemo<F> {
    /// No entry.
    pub(crate) fn new() -> Self {
        NeighbourhoodMemo {
            entries: [(F::NONE, 64, 0, 0); 2],
            next: 0,
        }
    }

    /// The split for front voxels `front` and first bit `b0`, from an entry or from `compute`.
    #[inline(always)]
    pub(crate) fn split(
        &mut self,
        front: &F,
        b0: usize,
        compute: impl FnOnce() -> (u64, u32),
    ) -> (u64, u32) {
        for (f, b, same, ao) in &self.entries {
            if *b == b0 && f.same_as(front) {
                return (*same, *ao);
            }
        }
        let (same, ao) = compute();
        self.entries[self.next & 1] = (*front, b0, same, ao);
        self.next ^= 1;
        (same, ao)
    }
}

/// Faces from which a line of 1 x 1 quads is written straight into the output (see
/// [`SliceFaces::units`]).
const DIRECT_MIN: u32 = 12;

impl<const D: usize> SliceFaces<'_, D> {
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
    /// Lines of [`DIRECT_MIN`] faces or more are written straight into the output (with the
    /// AVX-512 kernel where there is one), which saves copying them out of the slice's buffer
    /// but costs a capacity check per line: shorter lines go through the buffer. The rule
    /// does not depend on the instruction set, so neither does the order of the quads.
    #[inline(always)]
    pub(crate) fn units<const AO: bool>(
        &self,
        l: usize,
        bits: u64,
        known: &mut u64,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        if bits.count_ones() >= DIRECT_MIN {
            return match out.wide {
                Some(wide) => self.units_wide::<AO>(wide, l, bits, known, out),
                None => self.units_direct::<AO>(l, bits, known, out),
            };
        }
        let ids = self.line_ids(l);
        let front = self.front_lines(l);
        let word = self.position_size(l, 1, 1, 1);
        // The end in a local: the buffer's end is stored once, not once per quad (on an error
        // the whole output is dropped).
        let mut n = out.len;
        // The ids seen: checked against the cache of known ids once, after the line, instead
        // of once per face.
        let mut seen = 0u64;
        let mut m = bits;
        while m != 0 {
            let b = m.trailing_zeros() as usize;
            m &= m - 1;
            let (quad, id) = self.unit_quad::<AO>(ids, front, word, b);
            seen |= Self::seen_bit(id);
            out.buf[n & 4095] = quad;
            n += 1;
        }
        if seen & !*known != 0 {
            self.check_line(l, bits, known)?;
        }
        out.len = n;
        Ok(())
    }

    /// The 1 x 1 quad of the face at bit `b` (at least 1) of a line with ids `ids`, front
    /// lines `front` and word 0 `word` at bit 1, and the face's id.
    #[inline(always)]
    fn unit_quad<const AO: bool>(
        &self,
        ids: LineIds<'_>,
        front: Front,
        word: u32,
        b: usize,
    ) -> (PackedQuad, u32) {
        let id = ids.id(b);
        let quad = PackedQuad {
            position_size: word | ((b as u32).wrapping_sub(1) << Direction::<D>::SHIFT_B),
            face_ao_block: id << 11 | self.ao::<AO>(front, b) << 3 | D as u32,
        };
        (quad, id)
    }

    /// [`units`](Self::units) straight into the output.
    #[inline(always)]
    fn units_direct<const AO: bool>(
        &self,
        l: usize,
        bits: u64,
        known: &mut u64,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        let ids = self.line_ids(l);
        let front = self.front_lines(l);
        let word = self.position_size(l, 1, 1, 1);
        let mut seen = 0u64;
        let mut m = bits;
        // One capacity check for the line (as `push_bits`).
        out.out.extend((0..bits.count_ones()).map(|_| {
            let b = m.trailing_zeros() as usize;
            m &= m.wrapping_sub(1);
            let (quad, id) = self.unit_quad::<AO>(ids, front, word, b);
            seen |= Self::seen_bit(id);
            quad
        }));
        if seen & !*known != 0 {
            self.check_line(l, bits, known)?;
        }
        Ok(())
    }

    /// [`units`](Self::units) with the AVX-512 kernel: the line's AO bytes come as bit planes
    /// from whole-line operations on the front lines, and the quads are built 8 at a time.
    /// ±X lines have their ids strided; those of the faces are copied into a row first.
    #[inline(always)]
    fn units_wide<const AO: bool>(
        &self,
        wide: Wide,
        l: usize,
        bits: u64,
        known: &mut u64,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        let mut strided = [0u16; 64];
        let ids = match self.line_ids(l) {
            LineIds::Row(row) => row,
            ids @ LineIds::Strided { .. } => {
                let mut m = bits;
                while m != 0 {
                    let b = m.trailing_zeros() as usize;
                    m &= m - 1;
                    strided[b & 63] = ids.id(b) as u16;
                }
                &strided
            }
        };
        let (f0, f1, f2) = self.front_lines(l);
        let line = UnitLine {
            bits,
            ids,
            ao: if AO {
                ao_planes(&CORNER_OFFSETS[D], [f0, f1, f2])
            } else {
                [u64::MAX; 8]
            },
            first: u64::from(D as u32) << 32 | u64::from(self.position_size(l, 1, 1, 1)),
            shift: Direction::<D>::SHIFT_B,
        };
        if wide.unit_line(&line, out.out) & !*known != 0 {
            self.check_line(l, bits, known)?;
        }
        Ok(())
    }

    /// [`check`](Self::check)s the id of every face of `bits` in line `l`: the slow path of a
    /// line with an id the cache does not hold yet.
    #[cold]
    fn check_line(&self, l: usize, bits: u64, known: &mut u64) -> Result<(), MeshError> {
        let mut m = bits;
        while m != 0 {
            let b = m.trailing_zeros() as usize;
            m &= m - 1;
            self.check(self.id(l, b) << 11, known, l, b)?;
        }
        Ok(())
    }

    /// Appends a 1 x 1 quad for every face of `bits` (not empty) in line `l`, a line with
    /// [`many`] faces: faces that share the first face's key cost one add and one store each.
    #[inline(always)]
    pub(crate) fn line_units<const AO: bool>(
        &self,
        l: usize,
        bits: u64,
        memo: &mut NeighbourhoodMemo<Front>,
        known: &mut u64,
        out: &mut Quads<'_>,
    ) -> Result<(), MeshError> {
        let b0 = bits.trailing_zeros() as usize & 63;
        let (same_ao, key0) = if AO {
            let front = self.front_lines(l);
            let (same, ao0) = memo.split(&front, b0, || {
                (
                    Self::same_neighbourhood(front, b0),
                    self.ao::<AO>(front, b0),
                )
            });
            (same & bits, self.id(l, b0) << 11 | ao0 << 3)
        } else {
            (bits, self.key::<AO>(l, b0))
        };
        let ids = self.line_ids(l);
        let same_key = match ids {
            LineIds::Row(row) => faces_of_id(row, row[b0], same_ao),
            // ±X faces: the ids are strided, read one by one but compared without a branch.
            LineIds::Strided { .. } => {
                let id0 = key0 >> 11;
                let mut differ = 0u64;
                let mut m = same_ao;
                while m != 0 {
                    let b = m.trailing_zeros() as usize;
                    m &= m - 1;
                    differ |= u64::from(ids.id(b) != id0) << b;
                }
                same_ao & !differ
            }
        };
        self.check(key0, known, l, b0)?;
        let first = self.position_size(l, 1, 1, 1);
        out.push_bits(same_key, first, Direction::<D>::SHIFT_B, key0 | D as u32);
        let rest = bits & !same_key;
        if rest == 0 {
            return Ok(());
        }
        self.units::<AO>(l, rest, known, out)
    }
}
